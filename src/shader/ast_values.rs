//! What a GLSL value is made of, as far as the camera is concerned.

/// Compatibility-profile matrices that carry a camera transform.
pub const BUILTIN_MATRICES: [&str; 3] = [
    "gl_ModelViewProjectionMatrix",
    "gl_ProjectionMatrix",
    "gl_ModelViewMatrix",
];

#[derive(Clone, Debug, Default)]
pub struct Info {
    /// Uniform `mat4`s that took part, in multiplication order.
    pub matrices: Vec<String>,
    /// The value itself is a `mat4` (so multiplying it into a vector is a transform).
    pub is_mat4: bool,
    /// A `mat4` was multiplied with a non-matrix somewhere along the way.
    pub mat_mul: bool,
    /// The last step was a `.xyww`-style swizzle (or `z = w`): z copies w.
    pub far: bool,
    /// Built from literals and constants only.
    pub constant: bool,
    /// Something we cannot follow took part.
    pub unknown: bool,
    /// Read from a uniform array of vectors (a constant register file: Direct3D's constant
    /// buffers as wined3d declares them, `vec4 c[N]` of engines that upload matrices so).
    pub from_array: bool,
    /// Such an array's values multiplied with run-time data: a transform written out in
    /// components (`R.x = v.x * c[0].x + v.y * c[1].x + …`, as shader compilers scalarise
    /// `mul(v, M)`), which no matrix type names. Not a pass-through: the position is unknown.
    pub transformed: bool,
}

impl Info {
    /// A run-time value (attribute, varying, non-matrix uniform, local without initialiser).
    pub fn data() -> Info {
        Info::default()
    }

    pub fn constant() -> Info {
        Info {
            constant: true,
            ..Info::default()
        }
    }

    pub fn unknown() -> Info {
        Info {
            unknown: true,
            ..Info::default()
        }
    }

    pub fn matrix(gl_name: &str) -> Info {
        Info {
            matrices: vec![gl_name.to_string()],
            is_mat4: true,
            ..Info::default()
        }
    }

    /// The same value used as an operand: a swizzle or index result is no longer "far" and
    /// no longer a matrix.
    pub fn value(mut self) -> Info {
        self.far = false;
        self.is_mat4 = false;
        self
    }

    /// Any non-multiplicative combination (`+`, constructors, built-in calls, branches).
    pub fn combine(a: Info, b: Info) -> Info {
        let mut matrices = a.matrices;
        matrices.extend(b.matrices);
        Info {
            matrices,
            is_mat4: false,
            mat_mul: a.mat_mul || b.mat_mul,
            far: false,
            constant: a.constant && b.constant,
            unknown: a.unknown || b.unknown,
            from_array: a.from_array || b.from_array,
            transformed: a.transformed || b.transformed,
        }
    }

    /// `a * b`: a transform when exactly one side is a matrix (`M * v` or row-vector `v * M`).
    pub fn mult(a: Info, b: Info) -> Info {
        let transform = a.is_mat4 != b.is_mat4;
        let both = a.is_mat4 && b.is_mat4;
        let written_out = (a.from_array && !b.constant) || (b.from_array && !a.constant);
        let mut out = Info::combine(a, b);
        out.transformed |= written_out;
        out.mat_mul |= transform;
        out.is_mat4 = both;
        out
    }
}

/// `xyww`, `rgaa`, `stqq`: four components whose z copies w.
pub fn is_far_swizzle(field: &str) -> bool {
    let c: Vec<char> = field.chars().collect();
    c.len() == 4 && c[2] == c[3] && matches!(c[3], 'w' | 'a' | 'q')
}
