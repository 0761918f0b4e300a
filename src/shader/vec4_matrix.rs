//! Matrices held in `vec4` uniform arrays: Direct3D's constant registers as Wine's wined3d
//! passes them (`uniform vec4 vs_c[256]`), and engines that upload matrices as vec4s.
//!
//! Two shapes are recognised, anywhere in a shader: four component writes of one value, each
//! a dot product of the same vector with consecutive elements (`o.x = dot(v, c[k]); o.y =
//! dot(v, c[k+1]); …`: the rows of the matrix are `c[k..k+4]`), and `mat4(c[k], c[k+1],
//! c[k+2], c[k+3])` (its columns). Where the value goes is not followed: wined3d applies the
//! matrix in one shader object and writes `gl_Position` in another. The caller decides which
//! one is the position's (`multiview::replay::link`: the only one of the program).

use std::collections::HashMap;

use glsl_lang::ast::{self, AssignmentOpData, ExprData, FunIdentifierData, TypeSpecifierNonArrayData};
use glsl_lang::visitor::{Host, Visit, Visitor};

use super::ast_symbols::Program;

/// A 4x4 matrix held in four consecutive elements of a uniform array.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub struct Vec4Matrix {
    pub array: String,
    pub first: u32,
    /// The elements are the matrix's rows (dot products), else its columns (`mat4(…)`).
    pub rows: bool,
}

impl Vec4Matrix {
    /// The GL introspection name of its first element (`vs_c[0]`).
    pub fn first_name(&self) -> String {
        format!("{}[{}]", self.array, self.first)
    }
}

/// The vec4-array matrices `tu` applies, each once, in source order.
pub fn find(tu: &ast::TranslationUnit) -> Vec<Vec4Matrix> {
    let prog = Program::collect(tu);
    let mut c = Collector {
        prog: &prog,
        rows: HashMap::new(),
        found: Vec::new(),
    };
    tu.visit(&mut c);
    let mut groups: Vec<_> = c.rows.into_iter().collect();
    groups.sort_by_key(|(_, g)| g.order);
    for ((_, _, array), g) in groups {
        if let [Some(k), Some(k1), Some(k2), Some(k3)] = g.index
            && k1 == k + 1
            && k2 == k + 2
            && k3 == k + 3
        {
            c.found.push(Vec4Matrix {
                array,
                first: k,
                rows: true,
            });
        }
    }
    let mut seen = std::collections::HashSet::new();
    c.found.retain(|m| seen.insert(m.clone()));
    c.found
}

/// The element index each component of one value was given, and when the first was seen.
struct Rows {
    index: [Option<u32>; 4],
    order: usize,
}

struct Collector<'p, 'a> {
    prog: &'p Program<'a>,
    /// (written value, the vector dotted, array) → its components' element indices.
    rows: HashMap<(String, String, String), Rows>,
    found: Vec<Vec4Matrix>,
}

impl Visitor for Collector<'_, '_> {
    fn visit_expr(&mut self, e: &ast::Expr) -> Visit {
        match &**e {
            ExprData::Assignment(lhs, op, rhs) if matches!(&**op, AssignmentOpData::Equal) => {
                self.component_write(lhs, rhs)
            }
            ExprData::FunCall(f, args) => self.constructor(f, args),
            _ => {}
        }
        Visit::Children
    }
}

impl Collector<'_, '_> {
    /// `value.c = dot(v, a[k])` (either argument order).
    fn component_write(&mut self, lhs: &ast::Expr, rhs: &ast::Expr) {
        let ExprData::Dot(value, field) = &**lhs else { return };
        let Some(component) = component(field.as_str()) else {
            return;
        };
        let ExprData::FunCall(f, args) = &**rhs else { return };
        if callee(f) != Some("dot") || args.len() != 2 {
            return;
        }
        let (vector, (array, k)) = match (self.element(&args[0]), self.element(&args[1])) {
            (None, Some(el)) => (&args[0], el),
            (Some(el), None) => (&args[1], el),
            _ => return,
        };
        let (Some(value), Some(vector)) = (path(value), path(vector)) else {
            return;
        };
        let order = self.rows.len();
        let g = self.rows.entry((value, vector, array)).or_insert(Rows {
            index: [None; 4],
            order,
        });
        g.index[component] = Some(k);
    }

    /// `mat4(a[k], a[k+1], a[k+2], a[k+3])`.
    fn constructor(&mut self, f: &ast::FunIdentifier, args: &[ast::Expr]) {
        let FunIdentifierData::TypeSpecifier(ty) = &**f else {
            return;
        };
        if !matches!(&*ty.ty, TypeSpecifierNonArrayData::Mat4) || args.len() != 4 {
            return;
        }
        let elements: Option<Vec<(String, u32)>> = args.iter().map(|a| self.element(a)).collect();
        let Some(elements) = elements else { return };
        let (array, k) = elements[0].clone();
        if elements
            .iter()
            .enumerate()
            .all(|(i, (a, j))| *a == array && *j == k + i as u32)
        {
            self.found.push(Vec4Matrix {
                array,
                first: k,
                rows: false,
            });
        }
    }

    /// `a[k]` or `a[k].xyzw` of a uniform array `a`, with `k` a literal.
    fn element(&self, e: &ast::Expr) -> Option<(String, u32)> {
        let e: &ast::Expr = match &**e {
            ExprData::Dot(inner, f) if matches!(f.as_str(), "xyzw" | "rgba" | "stpq") => inner,
            _ => e,
        };
        let ExprData::Bracket(array, index) = &**e else {
            return None;
        };
        let ExprData::Variable(name) = &***array else {
            return None;
        };
        let sym = self.prog.globals.get(name.as_str())?;
        if !(sym.uniform && sym.is_array) {
            return None;
        }
        match &***index {
            ExprData::IntConst(k) => u32::try_from(*k).ok(),
            ExprData::UIntConst(k) => Some(*k),
            _ => None,
        }
        .map(|k| (name.as_str().to_string(), k))
    }
}

fn callee(f: &ast::FunIdentifier) -> Option<&str> {
    match &**f {
        FunIdentifierData::Expr(e) => match &***e {
            ExprData::Variable(id) => Some(id.as_str()),
            _ => None,
        },
        FunIdentifierData::TypeSpecifier(_) => None,
    }
}

fn component(field: &str) -> Option<usize> {
    match field {
        "x" | "r" | "s" => Some(0),
        "y" | "g" | "t" => Some(1),
        "z" | "b" | "p" => Some(2),
        "w" | "a" | "q" => Some(3),
        _ => None,
    }
}

/// A variable, an element with a literal index or a full swizzle of either, as text (the
/// key that ties the four component writes together).
fn path(e: &ast::Expr) -> Option<String> {
    match &**e {
        ExprData::Variable(id) => Some(id.as_str().to_string()),
        ExprData::Bracket(a, i) => {
            let index = match &***i {
                ExprData::IntConst(k) => k.to_string(),
                ExprData::UIntConst(k) => k.to_string(),
                _ => return None,
            };
            Some(format!("{}[{index}]", path(a)?))
        }
        ExprData::Dot(a, f) if matches!(f.as_str(), "xyzw" | "rgba" | "stpq") => path(a),
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glsl_lang::parse::DefaultParse;

    fn found(src: &str) -> Vec<Vec4Matrix> {
        find(&ast::TranslationUnit::parse(src).expect("parses"))
    }

    fn rows(array: &str, first: u32) -> Vec4Matrix {
        Vec4Matrix {
            array: array.into(),
            first,
            rows: true,
        }
    }

    #[test]
    fn wined3d_dot_products_are_rows() {
        // As wined3d 8.0 writes a vs_2_0 `dp4 oPos.x..w, v0, c0..c3`.
        let src = "#version 440\nuniform vec4 vs_c[256];\nvec4 vs_out[12];\nlayout(location = 0) in vec4 vs_in0;\n\
                   void setup_vs_output(in vec4[12]);\nvoid main()\n{\n\
                   vs_out[10].x = (dot(vs_in0.xyzw, vs_c[0].xyzw));\nvs_out[10].y = (dot(vs_in0.xyzw, vs_c[1].xyzw));\n\
                   vs_out[10].z = (dot(vs_in0.xyzw, vs_c[2].xyzw));\nvs_out[10].w = (dot(vs_in0.xyzw, vs_c[3].xyzw));\n\
                   setup_vs_output(vs_out);\n}\n";
        assert_eq!(found(src), vec![rows("vs_c", 0)]);
        assert_eq!(found(src)[0].first_name(), "vs_c[0]");
    }

    #[test]
    fn a_second_matrix_and_the_argument_order() {
        let src = "#version 330\nuniform vec4 c[16];\nin vec4 p;\nout vec4 world;\nvoid main()\n{\n\
                   world.x = dot(c[4], p); world.y = dot(c[5], p); world.z = dot(c[6], p); world.w = dot(c[7], p);\n\
                   gl_Position.x = dot(p, c[0]); gl_Position.y = dot(p, c[1]);\n\
                   gl_Position.z = dot(p, c[2]); gl_Position.w = dot(p, c[3]);\n}\n";
        assert_eq!(found(src), vec![rows("c", 4), rows("c", 0)]);
    }

    #[test]
    fn a_mat4_of_consecutive_elements_is_columns() {
        let src = "#version 330\nuniform vec4 m[8];\nin vec4 p;\nvoid main()\n{\n\
                   gl_Position = mat4(m[4], m[5], m[6], m[7]) * p;\n}\n";
        let want = Vec4Matrix {
            array: "m".into(),
            first: 4,
            rows: false,
        };
        assert_eq!(found(src), vec![want]);
    }

    #[test]
    fn incomplete_scattered_or_non_uniform_groups_are_not_matrices() {
        for body in [
            // three rows only
            "o.x = dot(p, c[0]); o.y = dot(p, c[1]); o.z = dot(p, c[2]);",
            // not consecutive
            "o.x = dot(p, c[0]); o.y = dot(p, c[2]); o.z = dot(p, c[4]); o.w = dot(p, c[6]);",
            // two different vectors
            "o.x = dot(p, c[0]); o.y = dot(q, c[1]); o.z = dot(p, c[2]); o.w = dot(p, c[3]);",
            // an index the source computes
            "o.x = dot(p, c[i]); o.y = dot(p, c[i + 1]); o.z = dot(p, c[2]); o.w = dot(p, c[3]);",
            // a local array
            "o.x = dot(p, l[0]); o.y = dot(p, l[1]); o.z = dot(p, l[2]); o.w = dot(p, l[3]);",
        ] {
            let src = format!(
                "#version 330\nuniform vec4 c[8];\nuniform int i;\nin vec4 p;\nin vec4 q;\nout vec4 o;\n\
                 void main()\n{{\nvec4 l[4];\n{body}\ngl_Position = p;\n}}\n"
            );
            assert_eq!(found(&src), vec![], "{body}");
        }
    }
}
