//! glibc's heap, tuned inside the process that renders, never through the environment.
//!
//! With llvmpipe, glibc gives the top of the heap back and grows it again at every flush of a
//! frame's rendering once the heap's layout allows it (an `sbrk` shrink, then page faults on
//! the regrowth): `cubes` 5x1 under `--mode auto` took 14.2 ms a frame against 5.8 ms with a
//! 256 MiB trim threshold and a 64 MiB top pad. The launcher used to put `MALLOC_*` variables
//! into the program's environment, which every process it starts inherits: Wine's helpers
//! then failed to map their shared data at random (issue 25). `mallopt` here changes this
//! process only, once its first context gets multiview, and not where the user set either
//! variable (glibc read those at start-up). The cost is memory the program would have
//! returned, never correctness.

use std::sync::Once;

const TRIM_THRESHOLD: libc::c_int = 256 << 20;
const TOP_PAD: libc::c_int = 64 << 20;

static TUNED: Once = Once::new();

pub fn tune_once() {
    TUNED.call_once(|| {
        let set = |var: &str| std::env::var_os(var).is_some();
        if set("MALLOC_TRIM_THRESHOLD_") || set("MALLOC_TOP_PAD_") {
            return;
        }
        // SAFETY: mallopt only changes glibc's tunables; any value is allowed at any time.
        let ok = unsafe {
            libc::mallopt(libc::M_TRIM_THRESHOLD, TRIM_THRESHOLD) == 1 && libc::mallopt(libc::M_TOP_PAD, TOP_PAD) == 1
        };
        crate::log::debug(format_args!(
            "heap: trim threshold 256 MiB, top pad 64 MiB for this process{}",
            if ok { "" } else { " (glibc refused)" }
        ));
    });
}
