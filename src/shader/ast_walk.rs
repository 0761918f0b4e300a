//! Classification of `gl_Position` writes on the glsl-lang AST.
//!
//! Each function body is walked in source order with an environment mapping every assigned
//! name to what its value is made of ([`Info`]), so `vec4 p = mvp * pos; gl_Position = p;`
//! resolves. Control flow is flattened: a name assigned in both branches keeps the later value,
//! which is what matters for the common straight-line vertex shader.

use std::collections::HashMap;

use glsl_lang::ast::{
    self, AssignmentOpData, BinaryOpData, DeclarationData, ExprData, ForInitStatementData, FunIdentifierData,
    IterationStatementData, JumpStatementData, SelectionRestStatementData, StatementData,
};

use super::PositionKind;
use super::ast_symbols::{Program, Sym, is_mat4};
use super::ast_values::{BUILTIN_MATRICES, Info, is_far_swizzle};
use super::findings::Findings;

pub fn walk(tu: &ast::TranslationUnit) -> Findings {
    let mut prog = Program::collect(tu);
    let (findings, writers) = walk_functions(&prog);
    if writers.is_empty() {
        return findings;
    }
    // A function that writes `gl_Position` from its parameters (wined3d's
    // `setup_vs_output(vs_out)`) counts where it is called, with its arguments' values; alone,
    // its parameters would look like plain data. Most shaders write it in `main` alone and are
    // walked once.
    prog.position_writers = writers;
    walk_functions(&prog).0
}

/// Every function body walked on its own: what the `gl_Position` writes are (those of a
/// function of `prog.position_writers` counted at its calls instead, where it has any), and
/// which functions other than `main` write it.
fn walk_functions(prog: &Program) -> (Findings, std::collections::HashSet<String>) {
    let mut findings = Findings::default();
    let mut writers = std::collections::HashSet::new();
    let mut called = std::collections::HashSet::new();
    let mut walked = Vec::new();
    for (name, defs) in &prog.functions {
        for def in defs {
            let mut scope = Scope::new(prog, true, 0);
            scope.walk_compound(&def.statement.statement_list);
            findings.writes_layer |= scope.writes_layer;
            if name != "main" && !scope.writes.is_empty() {
                writers.insert(name.clone());
            }
            called.extend(scope.inlined.drain());
            walked.push((name, scope.writes));
        }
    }
    for (name, writes) in walked {
        if called.contains(name) {
            continue;
        }
        for info in &writes {
            findings.add_write(info.kind(), &info.matrices);
        }
    }
    (findings, writers)
}

struct Scope<'p, 'a> {
    prog: &'p Program<'a>,
    env: HashMap<String, Info>,
    /// One entry per full `gl_Position =` write; component writes amend the last one.
    writes: Vec<Info>,
    writes_layer: bool,
    returns: Vec<Info>,
    /// False while evaluating a call's return value: its writes are counted by its own walk.
    record: bool,
    depth: usize,
    /// Functions of `prog.position_writers` whose write was taken into this walk at a call.
    inlined: std::collections::HashSet<String>,
}

impl<'p, 'a> Scope<'p, 'a> {
    fn new(prog: &'p Program<'a>, record: bool, depth: usize) -> Self {
        let env = HashMap::new();
        Scope {
            prog,
            env,
            writes: Vec::new(),
            writes_layer: false,
            returns: Vec::new(),
            record,
            depth,
            inlined: std::collections::HashSet::new(),
        }
    }

    fn walk_compound(&mut self, stmts: &[ast::Statement]) {
        stmts.iter().for_each(|s| self.walk_statement(s));
    }

    fn walk_statement(&mut self, stmt: &ast::Statement) {
        match &**stmt {
            StatementData::Declaration(d) => self.declare(d),
            StatementData::Expression(e) => e.0.iter().for_each(|e| self.effects(e)),
            StatementData::Selection(sel) => {
                self.effects(&sel.cond);
                match &*sel.rest {
                    SelectionRestStatementData::Statement(s) => self.walk_statement(s),
                    SelectionRestStatementData::Else(a, b) => {
                        self.walk_statement(a);
                        self.walk_statement(b);
                    }
                }
            }
            StatementData::Switch(sw) => self.walk_compound(&sw.body),
            StatementData::Iteration(it) => self.walk_iteration(it),
            StatementData::Jump(j) => {
                if let JumpStatementData::Return(Some(e)) = &**j {
                    self.effects(e);
                    let info = self.eval(e);
                    self.returns.push(info);
                }
            }
            StatementData::Compound(c) => self.walk_compound(&c.statement_list),
            StatementData::CaseLabel(_) => {}
        }
    }

    fn walk_iteration(&mut self, it: &ast::IterationStatement) {
        match &**it {
            IterationStatementData::While(_, body) => self.walk_statement(body),
            IterationStatementData::DoWhile(body, cond) => {
                self.walk_statement(body);
                self.effects(cond);
            }
            IterationStatementData::For(init, rest, body) => {
                match &**init {
                    ForInitStatementData::Declaration(d) => self.declare(d),
                    ForInitStatementData::Expression(e) => e.iter().for_each(|e| self.effects(e)),
                }
                rest.post_expr.iter().for_each(|e| self.effects(e));
                self.walk_statement(body);
            }
        }
    }

    fn declare(&mut self, decl: &ast::Declaration) {
        let DeclarationData::InitDeclaratorList(list) = &**decl else {
            return;
        };
        let mat = is_mat4(&list.head.ty.ty.ty);
        let head = list.head.name.as_ref().map(|n| (n, list.head.initializer.as_ref()));
        let tail = list.tail.iter().map(|t| (&t.ident.ident, t.initializer.as_ref()));
        for (name, init) in head.into_iter().chain(tail) {
            let mut info = match init.map(|i| &**i) {
                Some(ast::InitializerData::Simple(e)) => {
                    self.effects(e);
                    self.eval(e)
                }
                _ => Info::data(),
            };
            info.is_mat4 = mat;
            self.env.insert(name.as_str().to_string(), info);
        }
    }

    /// Finds the assignments inside an expression (they may nest in calls or comma lists).
    fn effects(&mut self, e: &ast::Expr) {
        match &**e {
            ExprData::Assignment(lhs, op, rhs) => {
                self.effects(rhs);
                self.assign(lhs, op, rhs);
            }
            ExprData::Unary(_, a) | ExprData::Dot(a, _) | ExprData::PostInc(a) | ExprData::PostDec(a) => {
                self.effects(a)
            }
            ExprData::Binary(_, a, b) | ExprData::Bracket(a, b) | ExprData::Comma(a, b) => {
                self.effects(a);
                self.effects(b);
            }
            ExprData::Ternary(c, a, b) => [c, a, b].into_iter().for_each(|x| self.effects(x)),
            ExprData::FunCall(f, args) => {
                args.iter().for_each(|a| self.effects(a));
                self.external_call(f);
                self.inline_position(f, args);
            }
            _ => {}
        }
    }

    /// A call of a function defined in another shader object may write `gl_Position`: what
    /// this object then does to it (wined3d's `pos_fixup` edits) works on an unknown value.
    fn external_call(&mut self, f: &ast::FunIdentifier) {
        if let FunIdentifierData::Expr(e) = &**f
            && let ExprData::Variable(id) = &***e
            && self.prog.declared_only.contains(id.as_str())
        {
            self.env.insert("gl_Position".to_string(), Info::unknown());
        }
    }

    /// A call of a function of this object that writes `gl_Position`: its write, with its
    /// parameters bound to the arguments, is a whole write here.
    fn inline_position(&mut self, f: &ast::FunIdentifier, args: &[ast::Expr]) {
        let FunIdentifierData::Expr(e) = &**f else { return };
        let ExprData::Variable(id) = &***e else { return };
        if !self.prog.position_writers.contains(id.as_str()) {
            return;
        }
        let Some(defs) = self.prog.functions.get(id.as_str()) else {
            return;
        };
        let Some(scopes) = self.called(defs, args) else {
            return;
        };
        let written = scopes
            .into_iter()
            .filter_map(|mut s| s.env.remove("gl_Position"))
            .reduce(Info::combine);
        let Some(info) = written else { return };
        self.inlined.insert(id.as_str().to_string());
        self.env.insert("gl_Position".to_string(), info.clone());
        if self.record {
            self.writes.push(info);
        }
    }

    fn assign(&mut self, lhs: &ast::Expr, op: &ast::AssignmentOp, rhs: &ast::Expr) {
        let value = match &**op {
            AssignmentOpData::Equal => self.eval(rhs),
            AssignmentOpData::Mult => Info::mult(self.eval(lhs), self.eval(rhs)),
            _ => Info::combine(self.eval(lhs), self.eval(rhs)),
        };
        let Some(root) = lvalue_root(lhs) else { return };
        let whole = matches!(&**lhs, ExprData::Variable(_));
        match root {
            "gl_Layer" | "gl_ViewportIndex" => self.writes_layer = true,
            "gl_Position" => self.assign_position(lhs, whole, value, rhs),
            _ if whole => {
                self.env.insert(root.to_string(), value);
            }
            _ => {
                let old = self.env.remove(root).unwrap_or_else(Info::data);
                self.env.insert(root.to_string(), Info::combine(old, value));
            }
        }
    }

    fn assign_position(&mut self, lhs: &ast::Expr, whole: bool, value: Info, rhs: &ast::Expr) {
        let info = if whole {
            value
        } else {
            let old = self.env.get("gl_Position").cloned().unwrap_or_else(Info::data);
            let z_from_w = matches!(&**lhs, ExprData::Dot(_, f) if f.as_str() == "z")
                && matches!(&**rhs, ExprData::Dot(_, f) if matches!(f.as_str(), "w" | "a" | "q"));
            let mut merged = Info::combine(old, value);
            merged.far = z_from_w;
            merged
        };
        self.env.insert("gl_Position".to_string(), info.clone());
        if !self.record {
            return;
        }
        match self.writes.last_mut() {
            Some(last) if !whole => *last = info,
            _ => self.writes.push(info),
        }
    }

    fn eval(&self, e: &ast::Expr) -> Info {
        match &**e {
            ExprData::Variable(id) => self.eval_name(id.as_str()),
            ExprData::IntConst(_)
            | ExprData::UIntConst(_)
            | ExprData::BoolConst(_)
            | ExprData::FloatConst(_)
            | ExprData::DoubleConst(_) => Info::constant(),
            ExprData::Unary(_, a) | ExprData::PostInc(a) | ExprData::PostDec(a) => self.eval(a).value(),
            ExprData::Binary(op, a, b) => match &**op {
                BinaryOpData::Mult => Info::mult(self.eval(a), self.eval(b)),
                _ => Info::combine(self.eval(a), self.eval(b)),
            },
            ExprData::Ternary(_, a, b) => Info::combine(self.eval(a), self.eval(b)),
            ExprData::Assignment(_, _, rhs) => self.eval(rhs),
            ExprData::Bracket(a, _) => self.eval_index(a),
            ExprData::Dot(a, field) => self.eval_dot(e, a, field.as_str()),
            ExprData::FunCall(f, args) => self.eval_call(f, args),
            ExprData::Comma(_, b) => self.eval(b),
        }
    }

    fn eval_name(&self, name: &str) -> Info {
        if let Some(info) = self.env.get(name) {
            return info.clone();
        }
        if name == "gl_in" {
            return Info::unknown(); // the previous stage's clip position: transform unknown here
        }
        if BUILTIN_MATRICES.contains(&name) {
            return Info::matrix(name);
        }
        self.prog.globals.get(name).map_or_else(Info::data, sym_info)
    }

    fn eval_index(&self, a: &ast::Expr) -> Info {
        let inner = self.eval(a);
        match self.resolve(a) {
            Some(sym) if sym.is_array => inner,
            _ => inner.value(), // indexing a matrix gives a column, no longer a matrix
        }
    }

    fn eval_dot(&self, whole: &ast::Expr, a: &ast::Expr, field: &str) -> Info {
        if let Some(sym) = self.resolve(whole) {
            return sym_info(sym);
        }
        let mut info = self.eval(a).value();
        info.far = is_far_swizzle(field);
        info
    }

    fn eval_call(&self, f: &ast::FunIdentifier, args: &[ast::Expr]) -> Info {
        let fold = |acc: Info, a: &ast::Expr| Info::combine(acc, self.eval(a));
        let name = match &**f {
            FunIdentifierData::TypeSpecifier(ty) => {
                let mut info = args.iter().fold(Info::constant(), fold);
                info.is_mat4 = is_mat4(&ty.ty);
                return info;
            }
            FunIdentifierData::Expr(e) => match &***e {
                ExprData::Variable(id) => id.as_str(),
                _ => return Info::unknown(),
            },
        };
        if name == "ftransform" {
            return Info::mult(Info::matrix("gl_ModelViewProjectionMatrix"), Info::data());
        }
        match self.prog.functions.get(name) {
            Some(defs) => self.eval_user_call(defs, args),
            None => args.iter().fold(Info::constant(), fold).value(),
        }
    }

    /// The value a user function returns, with its parameters bound to the arguments.
    fn eval_user_call(&self, defs: &[&ast::FunctionDefinition], args: &[ast::Expr]) -> Info {
        // Recursion is illegal GLSL, but no input may hang us.
        let Some(scopes) = self.called(defs, args) else {
            return Info::unknown();
        };
        scopes
            .into_iter()
            .flat_map(|s| s.returns)
            .reduce(Info::combine)
            .unwrap_or_else(Info::unknown)
    }

    /// The bodies of the overloads of a call that take its number of arguments, walked with
    /// their parameters bound to the arguments' values; `None` past the depth or call budget.
    fn called(&self, defs: &[&'a ast::FunctionDefinition], args: &[ast::Expr]) -> Option<Vec<Scope<'p, 'a>>> {
        if self.depth >= 8 || !self.prog.spend_call() {
            return None;
        }
        let arg_infos: Vec<Info> = args.iter().map(|a| self.eval(a)).collect();
        let walked = defs
            .iter()
            .filter(|d| d.prototype.parameters.len() == args.len())
            .map(|def| {
                let mut scope = Scope::new(self.prog, false, self.depth + 1);
                for (param, info) in def.prototype.parameters.iter().zip(&arg_infos) {
                    if let ast::FunctionParameterDeclarationData::Named(_, p) = &**param {
                        scope.env.insert(p.ident.ident.as_str().to_string(), info.clone());
                    }
                }
                scope.walk_compound(&def.statement.statement_list);
                scope
            });
        Some(walked.collect())
    }

    /// The global symbol an lvalue-like path names (`u`, `block.member`, `s[i].m`), unless a
    /// local shadows its root.
    fn resolve(&self, e: &ast::Expr) -> Option<&'p Sym> {
        match &**e {
            ExprData::Variable(id) if !self.env.contains_key(id.as_str()) => self.prog.globals.get(id.as_str()),
            ExprData::Bracket(a, _) => self.resolve(a).filter(|s| s.is_array),
            ExprData::Dot(a, f) => self.resolve(a)?.members.get(f.as_str()),
            _ => None,
        }
    }
}

fn sym_info(sym: &Sym) -> Info {
    match (sym.uniform, sym.is_mat4, sym.constant) {
        (true, true, _) => Info::matrix(&sym.gl_name),
        (true, false, false) if sym.is_array => Info {
            from_array: true,
            ..Info::data()
        },
        (_, _, true) => Info::constant(),
        (_, true, _) => Info {
            is_mat4: true,
            ..Info::data()
        },
        _ => Info::data(),
    }
}

/// The variable an assignment target starts from (`gl_Position` in `gl_Position.xy`).
fn lvalue_root(e: &ast::Expr) -> Option<&str> {
    match &**e {
        ExprData::Variable(id) => Some(id.as_str()),
        ExprData::Dot(a, _) | ExprData::Bracket(a, _) => lvalue_root(a),
        _ => None,
    }
}

impl Info {
    pub(super) fn kind(&self) -> PositionKind {
        if self.far {
            PositionKind::FarPlane
        } else if self.mat_mul || !self.matrices.is_empty() {
            PositionKind::MatrixMultiply
        } else if self.unknown || self.transformed {
            PositionKind::Unknown
        } else if self.constant {
            PositionKind::Constant
        } else {
            PositionKind::Identity
        }
    }
}
