//! Configuration: `HOLOINJECT_*` variables → typed [`Settings`] for the layer. The launcher
//! maps its options onto the same variables (`options::OPTIONS`), so running with
//! `LD_PRELOAD` and the variables by hand behaves exactly like `holoinject run`.

pub mod calibration;
pub mod cli;
pub mod comfort;
pub mod device;
pub mod live;
pub mod options;
pub mod parse;
pub mod preset;
mod preset_files;
pub mod preset_save;
#[cfg(test)]
mod tests_mutations;
mod values;
mod view;

use std::path::PathBuf;
use std::sync::OnceLock;
use view::ComfortChoice;

pub use values::{
    Boundary, Convergence, DEFAULT_FRAME_BUDGET_MS, FboScale, FboViews, FrameSet, GuardBand, Mode, Output, Present,
    Preview, RowsOn, SynthWarp, WeaveFilter,
};
pub use view::ViewSettings;

/// A message as one line whatever values it quotes (a preset string or a variable can hold
/// newlines and control characters): whitespace runs become one space, other control
/// characters are escaped.
pub fn one_line(s: &str) -> String {
    s.split_whitespace()
        .map(|w| {
            w.chars()
                .flat_map(|c| {
                    if c.is_control() {
                        c.escape_default().collect::<Vec<_>>()
                    } else {
                        vec![c]
                    }
                })
                .collect::<String>()
        })
        .collect::<Vec<_>>()
        .join(" ")
}

#[derive(Clone, Debug)]
pub struct Settings {
    pub dump_dir: Option<PathBuf>,
    pub dump_frames: FrameSet,
    pub exit_after: Option<u64>,
    /// `--record`: the video to write (its name gets the quilt tag).
    pub record: Option<PathBuf>,
    pub osmesa_boundary: Boundary,
    /// `--overlay`: live values drawn into the presented image after each change.
    pub overlay: bool,
    /// `--dump-disparity`: with `--dump`, each dumped frame's per-pixel disparity too.
    pub dump_disparity: bool,
    /// `--gpu-counts`: count per frame what the GPU is given, reported at exit.
    pub gpu_counts: bool,
    /// `--hotkeys`: the modifiers of the layer's key grabs (`None`: off).
    pub hotkeys: Option<Vec<String>>,
    pub view: ViewSettings,
}

impl Default for Settings {
    fn default() -> Self {
        Settings {
            dump_dir: None,
            dump_frames: FrameSet::Every(1),
            exit_after: None,
            record: None,
            osmesa_boundary: Boundary::Finish,
            overlay: false,
            dump_disparity: false,
            gpu_counts: false,
            hotkeys: parse::hotkeys(parse::DEFAULT_HOTKEYS).unwrap_or_default(),
            view: ViewSettings::default(),
        }
    }
}

impl Settings {
    /// Builds settings from a variable lookup; every bad value is reported (one line naming
    /// the variable) and replaced by its default, so the app keeps running.
    pub fn from_lookup(get: impl Fn(&str) -> Option<String>, report: &mut dyn FnMut(String)) -> Settings {
        Settings::from_sources(get, None, report)
    }

    /// As [`Settings::from_lookup`], with a preset's values under the variables (its values
    /// were checked when it was read).
    pub fn from_sources(
        get: impl Fn(&str) -> Option<String>,
        preset: Option<&preset::Preset>,
        report: &mut dyn FnMut(String),
    ) -> Settings {
        let mut s = Settings::default();
        let (mut quilt, mut tile, mut output, mut budget, mut present) = (None, None, None, None, None);
        let mut comfort = ComfortChoice::default();
        // The preset itself was chosen (and any problem with it reported) by the caller.
        for opt in options::OPTIONS
            .iter()
            .filter(|o| !o.launcher_only && o.long != "preset")
        {
            let var = opt.env_name();
            let value = match get(&var) {
                Some(value) => {
                    if let Err(e) = (opt.check)(&value) {
                        report(one_line(&format!("{var}={value}: {e}; ignored")));
                        continue;
                    }
                    value
                }
                None => match preset.and_then(|p| p.get(opt.long)) {
                    Some(value) => value.to_string(),
                    None => continue,
                },
            };
            match opt.long {
                "dump" => s.dump_dir = Some(PathBuf::from(value)),
                "dump-frames" => s.dump_frames = parse::frames(&value).unwrap_or(FrameSet::Every(1)),
                "record" => s.record = Some(PathBuf::from(value)),
                "exit-after" => s.exit_after = parse::frame_number(&value).ok(),
                "osmesa-boundary" => s.osmesa_boundary = parse::boundary(&value).unwrap_or(Boundary::Finish),
                "output" => output = parse::output(&value).ok(),
                "present" => present = parse::present(&value).ok(),
                "preview" => s.view.preview = parse::preview(&value).unwrap_or(Preview::Mono),
                "monitor" => s.view.monitor = parse::monitor(&value).ok(),
                "quilt" => quilt = parse::quilt(&value).ok(),
                "tile" => tile = parse::grid(&value).ok(),
                "overlay" => s.overlay = parse::switch(&value).unwrap_or(false),
                "dump-disparity" => s.dump_disparity = parse::switch(&value).unwrap_or(false),
                "gpu-counts" => s.gpu_counts = parse::switch(&value).unwrap_or(false),
                "hotkeys" => s.hotkeys = parse::hotkeys(&value).unwrap_or_default(),
                "frame-budget" => budget = parse::frame_budget(&value).ok().map(|b| (b, var)),
                "depth-remap" => comfort.remap = comfort::depth_remap(&value).ok(),
                "comfort" => comfort.on = comfort::comfort(&value).unwrap_or(true),
                _ => s.view.set(opt.long, &value),
            }
        }
        if let Err(e) = parse::reuse_with(s.view.reuse, s.view.mode) {
            report(format!("HOLOINJECT_REUSE: {e}; ignored"));
            s.view.reuse = false;
        }
        s.view.resolve(quilt, tile, output, present);
        s.view.apply_budget(budget, report);
        comfort.resolve(&mut s.view);
        s
    }

    /// Multiview is on unless the user asked for the app's own image.
    pub fn multiview(&self) -> bool {
        self.view.output != Output::Mono
    }

    /// Rendered views record each pixel's disparity (`shader::record`): the fast modes, the
    /// comfort pass, auto-convergence and `--dump-disparity` read it. Decided at link time, so a mode, a depth of
    /// field or an auto-convergence chosen later reads depth only.
    pub fn records_disparity(&self) -> bool {
        self.multiview()
            && self.view.disparity_record
            && (self.view.mode != Mode::Exact
                || self.view.comfort.post_pass()
                || self.view.convergence == Convergence::Auto
                || self.dump_disparity)
    }

    pub fn dumps(&self, frame: u64) -> bool {
        self.dump_dir.is_some() && self.dump_frames.contains(frame)
    }
}

static SETTINGS: OnceLock<Settings> = OnceLock::new();

/// The process's settings, read once: the preset for this program (or `HOLOINJECT_PRESET`)
/// under the environment.
pub fn settings() -> &'static Settings {
    SETTINGS.get_or_init(|| {
        let env = |k: &str| std::env::var(k).ok();
        let mut report = |msg: String| crate::log::error(format_args!("{}", one_line(&msg)));
        for var in options::OPTIONS.iter().map(|o| o.env_name()) {
            if let Err(std::env::VarError::NotUnicode(raw)) = std::env::var(&var) {
                report(one_line(&format!(
                    "{var}={}: not valid UTF-8; ignored",
                    raw.to_string_lossy()
                )));
            }
        }
        let chosen = preset::for_process(&env, &mut report);
        if let Some(c) = &chosen {
            let set: Vec<String> = c.preset.values.iter().map(|(k, v)| format!("{k}={v}")).collect();
            crate::log::info(format_args!(
                "preset {} (by {}): {}",
                c.preset.source,
                c.reason,
                set.join(" ")
            ));
        }
        Settings::from_sources(env, chosen.as_ref().map(|c| &c.preset), &mut report)
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::collections::HashMap;

    fn settings_of(vars: &[(&str, &str)]) -> (Settings, Vec<String>) {
        let map: HashMap<String, String> = vars.iter().map(|(k, v)| (k.to_string(), v.to_string())).collect();
        let mut errors = vec![];
        let s = Settings::from_lookup(|k| map.get(k).cloned(), &mut |e| errors.push(e));
        (s, errors)
    }

    #[test]
    fn reads_dump_and_exit_variables() {
        let (s, errors) = settings_of(&[
            ("HOLOINJECT_DUMP", "/tmp/d"),
            ("HOLOINJECT_DUMP_FRAMES", "2,4"),
            ("HOLOINJECT_EXIT_AFTER", "4"),
        ]);
        assert!(errors.is_empty());
        assert!(s.dumps(4) && !s.dumps(3));
        assert_eq!(s.exit_after, Some(4));
    }

    #[test]
    fn bad_values_name_the_variable_and_fall_back() {
        let (s, errors) = settings_of(&[("HOLOINJECT_EXIT_AFTER", "soon"), ("HOLOINJECT_QUILT", "8by6")]);
        assert_eq!(s.exit_after, None);
        assert_eq!(s.view.quilt, (8, 6));
        assert_eq!(errors.len(), 2);
        assert!(errors.iter().any(|e| e.starts_with("HOLOINJECT_QUILT=8by6")));
        assert!(errors.iter().any(|e| e.starts_with("HOLOINJECT_EXIT_AFTER=soon")));
    }

    #[test]
    fn the_environment_wins_over_a_preset() {
        let (p, skipped) = preset::parse("quilt = \"5x9\"\nconvergence = 40\nfocus = 0.02\n", "t.toml").unwrap();
        assert!(skipped.is_empty());
        let env: HashMap<String, String> = [("HOLOINJECT_QUILT".to_string(), "3x3".to_string())].into();
        let mut errors = vec![];
        let s = Settings::from_sources(|k| env.get(k).cloned(), Some(&p), &mut |e| errors.push(e));
        assert!(errors.is_empty(), "{errors:?}");
        assert_eq!(s.view.quilt, (3, 3));
        assert_eq!(s.view.convergence, Convergence::Fixed(40.0));
        assert_eq!(s.view.focus, 0.02);
    }

    #[test]
    fn reuse_needs_a_fast_mode() {
        let (s, errors) = settings_of(&[("HOLOINJECT_REUSE", "1"), ("HOLOINJECT_MODE", "hybrid:2")]);
        assert!(s.view.reuse && errors.is_empty(), "{errors:?}");
        let (s, errors) = settings_of(&[("HOLOINJECT_REUSE", "1")]);
        assert!(!s.view.reuse);
        assert_eq!(errors.len(), 1);
        assert!(errors[0].starts_with("HOLOINJECT_REUSE: --reuse needs"), "{errors:?}");
        let (p, _) = preset::parse("mode = \"synth\"\nreuse = true\n", "t.toml").unwrap();
        let mut errors = vec![];
        let s = Settings::from_sources(|_| None, Some(&p), &mut |e| errors.push(e));
        assert!(s.view.reuse && errors.is_empty(), "{errors:?}");
    }

    #[test]
    fn comfort_defaults_come_from_the_device_and_comfort_off_wins() {
        let (s, errors) = settings_of(&[("HOLOINJECT_DEVICE", "portrait")]);
        assert!(errors.is_empty(), "{errors:?}");
        assert_eq!(s.view.comfort.remap, Some(comfort::DEFAULT_RANGE));
        let (s, _) = settings_of(&[("HOLOINJECT_DEVICE", "portrait"), ("HOLOINJECT_DEPTH_REMAP", "off")]);
        assert_eq!(
            (s.view.comfort.remap, s.view.comfort.range),
            (None, Some(comfort::DEFAULT_RANGE))
        );
        let (s, _) = settings_of(&[("HOLOINJECT_DEPTH_REMAP", "5,6,7,8"), ("HOLOINJECT_DOF", "on")]);
        assert_eq!(s.view.comfort.range().back, 6.0);
        assert_eq!(s.view.comfort.dof, Some(1.0));
        let (s, _) = settings_of(&[
            ("HOLOINJECT_DEVICE", "go"),
            ("HOLOINJECT_EDGE_FADE", "30"),
            ("HOLOINJECT_COMFORT", "off"),
        ]);
        assert_eq!(s.view.comfort, comfort::ComfortSettings::default());
        // Without a device nothing is on.
        assert_eq!(settings_of(&[]).0.view.comfort, comfort::ComfortSettings::default());
        let (_, errors) = settings_of(&[("HOLOINJECT_DEPTH_REMAP", "1,2,3")]);
        assert!(
            errors[0].starts_with("HOLOINJECT_DEPTH_REMAP=1,2,3: `1,2,3`: expected"),
            "{errors:?}"
        );
    }

    /// The comfort effects changed live (`holoinject ctl set`, the R/F/E hotkeys) go through
    /// `ViewSettings::set` like the other live keys.
    #[test]
    fn comfort_effects_change_live() {
        let (mut s, _) = settings_of(&[("HOLOINJECT_DEVICE", "portrait")]);
        for key in ["depth-remap", "dof", "edge-fade"] {
            assert!(live::key(key).is_some(), "{key} is not live");
        }
        s.view.set("dof", "2");
        s.view.set("edge-fade", "24");
        assert_eq!((s.view.comfort.dof, s.view.comfort.edge_fade), (Some(2.0), Some(24.0)));
        s.view.set("depth-remap", "off");
        assert_eq!(s.view.comfort.remap, None);
        assert_eq!(
            s.view.comfort.range,
            Some(comfort::DEFAULT_RANGE),
            "the fade measures from the device's"
        );
        s.view.set("depth-remap", "5,6,7,8");
        assert_eq!(s.view.comfort.range().back, 6.0);
        s.view.set("dof", "off");
        assert_eq!(s.view.comfort.dof, None);
        // A bad value changes nothing.
        s.view.set("depth-remap", "1,2");
        assert_eq!(s.view.comfort.range().back, 6.0);
    }

    #[test]
    fn every_option_has_help_and_a_distinct_variable() {
        let mut names: Vec<String> = options::OPTIONS.iter().map(|o| o.env_name()).collect();
        names.sort();
        names.dedup();
        assert_eq!(names.len(), options::OPTIONS.len());
        assert!(options::OPTIONS.iter().all(|o| !o.help.is_empty()));
    }
}
