//! Global symbols of a parsed shader: which names are `uniform mat4`s (also inside uniform
//! blocks and uniform structs), constants and inputs, and the user functions.

use std::collections::HashMap;

use glsl_lang::ast::{
    self, DeclarationData, ExternalDeclarationData, StorageQualifierData, StructFieldSpecifier, TypeQualifierSpecData,
    TypeSpecifierNonArrayData,
};

/// A global name (or a member reachable through `.`).
#[derive(Clone, Debug, Default)]
pub struct Sym {
    pub uniform: bool,
    pub constant: bool,
    pub is_mat4: bool,
    pub is_array: bool,
    /// The name GL introspection uses (`Block.member`, `s.member`, or the plain name).
    pub gl_name: String,
    pub members: HashMap<String, Sym>,
}

/// Everything the walker needs to resolve names outside a function body.
#[derive(Default)]
pub struct Program<'a> {
    pub globals: HashMap<String, Sym>,
    pub functions: HashMap<String, Vec<&'a ast::FunctionDefinition>>,
    /// Functions this shader object only declares (defined in another object of the
    /// program, as wined3d's `setup_vs_output`, which writes `gl_Position`).
    pub declared_only: std::collections::HashSet<String>,
    structs: HashMap<String, Vec<StructFieldSpecifier>>,
    /// User-function bodies evaluated so far (see `spend_call`).
    calls: std::cell::Cell<u32>,
    /// Functions other than `main` that write `gl_Position` themselves (wined3d's
    /// `setup_vs_output`): their write counts where they are called (`ast_walk::walk`).
    pub position_writers: std::collections::HashSet<String>,
}

/// Most user-function bodies one analysis evaluates. Real shaders need tens; a function that
/// calls itself several times (illegal, but fuzzing made one) would otherwise cost
/// calls^depth walks: seconds at link time.
const CALL_BUDGET: u32 = 2000;

impl<'a> Program<'a> {
    /// Takes one user-function evaluation from the budget; false once it is spent.
    pub fn spend_call(&self) -> bool {
        let used = self.calls.get();
        self.calls.set(used.saturating_add(1));
        used < CALL_BUDGET
    }

    pub fn collect(tu: &'a ast::TranslationUnit) -> Program<'a> {
        let mut prog = Program::default();
        for decl in &tu.0 {
            match &**decl {
                ExternalDeclarationData::FunctionDefinition(f) => {
                    let name = f.prototype.name.as_str().to_string();
                    prog.functions.entry(name).or_default().push(f);
                }
                ExternalDeclarationData::Declaration(d) => prog.declaration(d),
                ExternalDeclarationData::Preprocessor(_) => {}
            }
        }
        let declared: Vec<String> =
            tu.0.iter()
                .filter_map(|d| match &**d {
                    ExternalDeclarationData::Declaration(decl) => match &**decl {
                        DeclarationData::FunctionPrototype(p) => Some(p.name.as_str().to_string()),
                        _ => None,
                    },
                    _ => None,
                })
                .collect();
        prog.declared_only = declared
            .into_iter()
            .filter(|n| !prog.functions.contains_key(n))
            .collect();
        prog
    }

    fn declaration(&mut self, decl: &ast::Declaration) {
        match &**decl {
            DeclarationData::InitDeclaratorList(list) => self.init_list(list),
            DeclarationData::Block(block) => self.block(block),
            _ => {}
        }
    }

    fn init_list(&mut self, list: &ast::InitDeclaratorList) {
        let head = &list.head;
        if let TypeSpecifierNonArrayData::Struct(spec) = &*head.ty.ty.ty
            && let Some(name) = &spec.name
        {
            self.structs.insert(name.as_str().to_string(), spec.fields.clone());
        }
        let quals = Qualifiers::of(head.ty.qualifier.as_ref());
        let array = head.ty.ty.array_specifier.is_some();
        let mut names: Vec<(&str, bool)> = Vec::new();
        if let Some(name) = &head.name {
            names.push((name.as_str(), array || head.array_specifier.is_some()));
        }
        for tail in &list.tail {
            names.push((tail.ident.ident.as_str(), array || tail.ident.array_spec.is_some()));
        }
        for (name, is_array) in names {
            let sym = self.sym_of_type(&head.ty.ty, name.to_string(), quals, is_array, 0);
            self.globals.insert(name.to_string(), sym);
        }
    }

    fn block(&mut self, block: &ast::Block) {
        let quals = Qualifiers::of(Some(&block.qualifier));
        let block_name = block.name.as_str();
        let instance = block.identifier.as_ref().map(|i| i.ident.as_str().to_string());
        let mut members = HashMap::new();
        for field in &block.fields {
            for id in &field.identifiers {
                let name = id.ident.as_str().to_string();
                let gl_name = match instance {
                    Some(_) => format!("{block_name}.{name}"),
                    None => name.clone(),
                };
                let sym = self.sym_of_type(&field.ty, gl_name, quals, id.array_spec.is_some(), 0);
                members.insert(name, sym);
            }
        }
        match instance {
            Some(inst) => {
                let sym = Sym {
                    uniform: quals.uniform,
                    gl_name: inst.clone(),
                    members,
                    ..Sym::default()
                };
                self.globals.insert(inst, sym);
            }
            None => self.globals.extend(members),
        }
    }

    fn sym_of_type(
        &self,
        ty: &ast::TypeSpecifier,
        gl_name: String,
        quals: Qualifiers,
        is_array: bool,
        depth: usize,
    ) -> Sym {
        let members = match &*ty.ty {
            TypeSpecifierNonArrayData::TypeName(t) if depth < 4 => {
                self.struct_members(self.structs.get(t.as_str()), &gl_name, quals, depth)
            }
            TypeSpecifierNonArrayData::Struct(s) if depth < 4 => {
                self.struct_members(Some(&s.fields), &gl_name, quals, depth)
            }
            _ => HashMap::new(),
        };
        Sym {
            uniform: quals.uniform,
            constant: quals.constant,
            is_mat4: is_mat4(&ty.ty),
            is_array: is_array || ty.array_specifier.is_some(),
            gl_name,
            members,
        }
    }

    fn struct_members(
        &self,
        fields: Option<&Vec<StructFieldSpecifier>>,
        prefix: &str,
        quals: Qualifiers,
        depth: usize,
    ) -> HashMap<String, Sym> {
        let mut members = HashMap::new();
        for field in fields.into_iter().flatten() {
            for id in &field.identifiers {
                let name = id.ident.as_str().to_string();
                let gl_name = format!("{prefix}.{name}");
                let array = id.array_spec.is_some();
                let sym = self.sym_of_type(&field.ty, gl_name, quals, array, depth + 1);
                members.insert(name, sym);
            }
        }
        members
    }
}

/// `mat4`, `mat4x4` and their double versions: the matrices a camera transform is made of.
pub fn is_mat4(ty: &TypeSpecifierNonArrayData) -> bool {
    use TypeSpecifierNonArrayData as T;
    matches!(ty, T::Mat4 | T::Mat44 | T::DMat4 | T::DMat44)
}

#[derive(Clone, Copy, Default)]
struct Qualifiers {
    uniform: bool,
    constant: bool,
}

impl Qualifiers {
    fn of(q: Option<&ast::TypeQualifier>) -> Qualifiers {
        let mut out = Qualifiers::default();
        for spec in q.map(|q| q.qualifiers.as_slice()).unwrap_or_default() {
            if let TypeQualifierSpecData::Storage(s) = &**spec {
                match &**s {
                    StorageQualifierData::Uniform => out.uniform = true,
                    StorageQualifierData::Const => out.constant = true,
                    _ => {}
                }
            }
        }
        out
    }
}
