//! Text-only analysis for sources glsl-lang refuses: a token scan without macro expansion or
//! types. It answers what gates the rewrite (does it write `gl_Position`, `gl_Layer`) exactly,
//! and the position kind conservatively: matrices found, `.xyww`, constant, else `Unknown`.

use std::collections::HashMap;

use super::PositionKind;
use super::ast_values::{BUILTIN_MATRICES, is_far_swizzle};
use super::findings::Findings;
use super::text::{Token, tokens};

const ASSIGN_OPS: [&str; 6] = ["=", "+=", "-=", "*=", "/=", "%="];
const MAX_DEPTH: usize = 8;

pub fn scan(blanked: &str) -> Findings {
    let toks = tokens(blanked);
    let uniforms = mat4_uniforms(&toks);
    let mut env: HashMap<String, Vec<Token>> = HashMap::new();
    let mut findings = Findings::default();
    for stmt in toks.split(|t| t.is_punct(";") || t.is_punct("{") || t.is_punct("}")) {
        let Some(at) = stmt.iter().position(|t| ASSIGN_OPS.iter().any(|op| t.is_punct(op))) else {
            continue;
        };
        let (lhs, rhs) = (&stmt[..at], &stmt[at + 1..]);
        let Some((root, component)) = lvalue(lhs) else { continue };
        match root.as_str() {
            "gl_Layer" | "gl_ViewportIndex" => findings.writes_layer = true,
            "gl_Position" => position_write(&mut findings, &uniforms, &env, component, rhs),
            _ => {
                env.insert(root, rhs.to_vec());
            }
        }
    }
    findings
}

fn position_write(
    findings: &mut Findings,
    uniforms: &HashMap<String, String>,
    env: &HashMap<String, Vec<Token>>,
    component: Option<&str>,
    rhs: &[Token],
) {
    let mut class = Class::default();
    class.visit(rhs, uniforms, env, 0);
    let z_from_w = component == Some("z") && ends_with_swizzle(rhs, |s| matches!(s, "w" | "a" | "q"));
    if component.is_some() && findings.writes_position {
        if z_from_w {
            findings.kind = Some(PositionKind::FarPlane);
        }
        return;
    }
    findings.add_write(class.kind(), &class.matrices);
}

#[derive(Default)]
struct Class {
    matrices: Vec<String>,
    far: bool,
    data: bool,
}

impl Class {
    fn visit(
        &mut self,
        rhs: &[Token],
        uniforms: &HashMap<String, String>,
        env: &HashMap<String, Vec<Token>>,
        depth: usize,
    ) {
        self.far |= depth == 0 && ends_with_swizzle(rhs, is_far_swizzle);
        for (i, tok) in rhs.iter().enumerate() {
            let Token::Ident(name) = tok else { continue };
            let after_dot = i > 0 && rhs[i - 1].is_punct(".");
            let member = rhs
                .get(i + 2)
                .filter(|_| rhs.get(i + 1).is_some_and(|t| t.is_punct(".")));
            if after_dot && !uniforms.contains_key(name) {
                continue; // a swizzle or a member already handled with its instance
            }
            if name == "ftransform" || BUILTIN_MATRICES.contains(&name.as_str()) {
                let gl = if name == "ftransform" {
                    "gl_ModelViewProjectionMatrix"
                } else {
                    name
                };
                self.matrices.push(gl.to_string());
            } else if let Some(gl) = member_uniform(name, member, uniforms) {
                self.matrices.push(gl);
            } else if let Some(gl) = uniforms.get(name).filter(|_| !after_dot) {
                self.matrices.push(gl.clone());
            } else if let Some(def) = env.get(name).filter(|_| depth < MAX_DEPTH) {
                self.visit(def, uniforms, env, depth + 1);
            } else if !is_type_keyword(name) {
                self.data = true;
            }
        }
    }

    fn kind(&self) -> PositionKind {
        if self.far {
            PositionKind::FarPlane
        } else if !self.matrices.is_empty() {
            PositionKind::MatrixMultiply
        } else if !self.data {
            PositionKind::Constant
        } else {
            PositionKind::Unknown
        }
    }
}

/// `instance.member` of an instanced uniform block, keyed as `instance.member`.
fn member_uniform(name: &str, member: Option<&Token>, uniforms: &HashMap<String, String>) -> Option<String> {
    let Some(Token::Ident(m)) = member else { return None };
    uniforms.get(&format!("{name}.{m}")).cloned()
}

fn ends_with_swizzle(rhs: &[Token], pred: impl Fn(&str) -> bool) -> bool {
    match rhs {
        [.., dot, Token::Ident(s)] if dot.is_punct(".") => pred(s),
        [.., dot, Token::Ident(s), close] if dot.is_punct(".") && close.is_punct(")") => pred(s),
        _ => false,
    }
}

/// The assigned variable and the component written, from `name`, `type name`, `name.xy`.
fn lvalue(lhs: &[Token]) -> Option<(String, Option<&str>)> {
    match lhs {
        [.., Token::Ident(root), dot, Token::Ident(c)] if dot.is_punct(".") => Some((root.clone(), Some(c.as_str()))),
        [.., Token::Ident(root)] => Some((root.clone(), None)),
        _ => None,
    }
}

fn is_type_keyword(name: &str) -> bool {
    let base = name.trim_end_matches(|c: char| c.is_ascii_digit() || c == 'x');
    matches!(
        base,
        "vec"
            | "ivec"
            | "uvec"
            | "bvec"
            | "dvec"
            | "mat"
            | "dmat"
            | "float"
            | "int"
            | "uint"
            | "bool"
            | "double"
            | "highp"
            | "mediump"
            | "lowp"
            | "const"
    )
}

/// Uniform `mat4` names as GL names them, keyed by how the code refers to them
/// (`name`, or `instance.member` for instanced blocks).
fn mat4_uniforms(toks: &[Token]) -> HashMap<String, String> {
    let mut out = HashMap::new();
    let mut i = 0;
    while i < toks.len() {
        if !toks[i].is_ident("uniform") {
            i += 1;
            continue;
        }
        let mut j = i + 1;
        while toks
            .get(j)
            .is_some_and(|t| ["highp", "mediump", "lowp"].iter().any(|p| t.is_ident(p)))
        {
            j += 1;
        }
        let Some(Token::Ident(ty)) = toks.get(j) else { break };
        if toks.get(j + 1).is_some_and(|t| t.is_punct("{")) {
            i = block_uniforms(toks, j, ty, &mut out);
        } else {
            let end = toks[j..]
                .iter()
                .position(|t| t.is_punct(";"))
                .map_or(toks.len(), |e| j + e);
            if is_mat4_name(ty) {
                for name in declared_names(&toks[j + 1..end]) {
                    out.insert(name.clone(), name);
                }
            }
            i = end;
        }
    }
    out
}

/// Members of `uniform Block { ... } [instance];` starting at the block name; returns the
/// index after the block.
fn block_uniforms(toks: &[Token], at: usize, block: &str, out: &mut HashMap<String, String>) -> usize {
    let close = toks[at..]
        .iter()
        .position(|t| t.is_punct("}"))
        .map_or(toks.len(), |e| at + e);
    let instance = match toks.get(close + 1) {
        Some(Token::Ident(inst)) => Some(inst.clone()),
        _ => None,
    };
    for field in toks[at + 2..close].split(|t| t.is_punct(";")) {
        let Some(ty_at) = field
            .iter()
            .position(|t| matches!(t, Token::Ident(n) if is_mat4_name(n)))
        else {
            continue;
        };
        for name in declared_names(&field[ty_at + 1..]) {
            match &instance {
                Some(inst) => out.insert(format!("{inst}.{name}"), format!("{block}.{name}")),
                None => out.insert(name.clone(), name),
            };
        }
    }
    close + 1
}

fn is_mat4_name(ty: &str) -> bool {
    matches!(ty, "mat4" | "mat4x4" | "dmat4" | "dmat4x4")
}

/// `a, b[4], c` → `a`, `b`, `c` (array sizes skipped).
fn declared_names(toks: &[Token]) -> Vec<String> {
    let mut names = Vec::new();
    let mut depth = 0;
    for t in toks {
        match t {
            Token::Punct(p) if p == "[" => depth += 1,
            Token::Punct(p) if p == "]" => depth -= 1,
            Token::Ident(n) if depth == 0 => names.push(n.clone()),
            _ => {}
        }
    }
    names
}
