//! Every option, defined once: the launcher parses and documents them from this table, the
//! layer reads the matching `HOLOINJECT_*` variables with the same value checks.

/// One launcher option `--long`, read by the layer as `HOLOINJECT_LONG` (dashes → underscores).
pub struct OptDef {
    pub long: &'static str,
    /// Value syntax shown in help; empty for flags.
    pub value: &'static str,
    pub help: &'static str,
    /// Checks a value; `Err` is a one-line reason. Values of options the layer cannot honour
    /// yet are rejected here, so nothing is silently ignored.
    pub check: fn(&str) -> Result<(), String>,
    /// Launcher-only: not passed to the layer.
    pub launcher_only: bool,
}

impl OptDef {
    pub fn env_name(&self) -> String {
        format!(
            "HOLOINJECT_{}",
            self.long.to_ascii_uppercase().replace('-', "_")
        )
    }
}

/// The multiview features these options configure arrive with issue #3 (exact quilt).
const PLANNED: &str =
    "multiview output is not available in this build yet; only pass-through (--output mono) works";

pub static OPTIONS: &[OptDef] = &[
    OptDef {
        long: "quilt",
        value: "CxR",
        help: "quilt columns x rows (views = C*R)",
        check: |v| {
            super::parse::grid(v)?;
            Err(PLANNED.into())
        },
        launcher_only: false,
    },
    OptDef {
        long: "tile",
        value: "WxH",
        help: "size of one view's tile in the quilt, pixels",
        check: |v| {
            super::parse::grid(v)?;
            Err(PLANNED.into())
        },
        launcher_only: false,
    },
    OptDef {
        long: "device",
        value: "NAME|PATH",
        help: "display calibration: a preset name or a visual.json",
        check: |_| Err(PLANNED.into()),
        launcher_only: false,
    },
    OptDef {
        long: "preset",
        value: "NAME|PATH",
        help: "application preset (TOML)",
        check: |_| Err(PLANNED.into()),
        launcher_only: false,
    },
    OptDef {
        long: "mode",
        value: "exact|synth|hybrid:K|auto",
        help: "how views are made",
        check: |v| {
            super::parse::mode(v)?;
            Err(PLANNED.into())
        },
        launcher_only: false,
    },
    OptDef {
        long: "output",
        value: "native|quilt|sbs|anaglyph|mono",
        help: "what is presented at swap (default mono)",
        check: super::parse::output,
        launcher_only: false,
    },
    OptDef {
        long: "depthiness",
        value: "S",
        help: "disparity at infinity (NDC) between centre and outermost view",
        check: |v| {
            super::parse::finite(v)?;
            Err(PLANNED.into())
        },
        launcher_only: false,
    },
    OptDef {
        long: "convergence",
        value: "auto|C",
        help: "eye-space distance of the zero-parallax plane",
        check: |v| {
            if v != "auto" {
                super::parse::positive(v)?;
            }
            Err(PLANNED.into())
        },
        launcher_only: false,
    },
    OptDef {
        long: "focus",
        value: "F",
        help: "post-hoc zero-parallax shift (NDC)",
        check: |v| {
            super::parse::finite(v)?;
            Err(PLANNED.into())
        },
        launcher_only: false,
    },
    OptDef {
        long: "dump",
        value: "DIR",
        help: "write presented frames as PNG into DIR",
        check: super::parse::nonempty,
        launcher_only: false,
    },
    OptDef {
        long: "dump-frames",
        value: "LIST|every:N",
        help: "frames to dump, e.g. 1,10,30 or every:10 (default: every frame)",
        check: |v| super::parse::frames(v).map(|_| ()),
        launcher_only: false,
    },
    OptDef {
        long: "exit-after",
        value: "N",
        help: "exit the program (status 0) right after frame N is presented and dumped",
        check: |v| super::parse::frame_number(v).map(|_| ()),
        launcher_only: false,
    },
    OptDef {
        long: "osmesa-boundary",
        value: "finish|flush",
        help: "call that ends a frame for OSMesa contexts, which never swap (default finish)",
        check: |v| super::parse::boundary(v).map(|_| ()),
        launcher_only: false,
    },
    OptDef {
        long: "log",
        value: "LEVEL",
        help: "stderr log level: off|error|warn|info|debug|trace (default warn)",
        check: |v| {
            crate::log::Level::parse(v)
                .map(|_| ())
                .ok_or_else(|| "expected off|error|warn|info|debug|trace".into())
        },
        launcher_only: false,
    },
    OptDef {
        long: "dry-run",
        value: "",
        help: "print the environment and command instead of running it",
        check: |_| Ok(()),
        launcher_only: true,
    },
];

pub fn find(long: &str) -> Option<&'static OptDef> {
    OPTIONS.iter().find(|o| o.long == long)
}
