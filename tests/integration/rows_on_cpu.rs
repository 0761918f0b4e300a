//! The row warp's scan on this process's threads (`--rows-on cpu`, what `auto` picks under
//! llvmpipe) against the compute pass it stands in for, on the same frames of the same
//! programs: what a viewer sees must not depend on where the scan ran.

use crate::synthesis::quilt_in;
use crate::util::*;

/// The trace line of frame 3's synthesis passes.
fn passes(log: &str) -> &str {
    log.lines()
        .rfind(|l| l.contains("synthesis passes:"))
        .unwrap_or_else(|| panic!("no synthesis passes traced:\n{log}"))
}

/// Every synthesised view within a level or two of the compute pass's (the CPU mixes colours
/// in integer steps of 1/256, the shader in floats: measured 80.9 dB on cubes at 8x6; a view
/// one pixel off would score below 30), the rendered view bit-identical; the CPU's colour goes
/// straight into the tiles (no resolve pass) where nothing reads their depth, and on a
/// scene of small objects over a far background (asteroids) as well as planes (cubes).
#[test]
fn row_warp_on_the_cpu_matches_the_compute_pass() {
    require_display();
    for (program, quilt, centre) in [("cubes", "5x1", 2), ("asteroids", "5x3", 7)] {
        let dir = temp_dir(&format!("rows_on_cpu_{program}"));
        let (cols, rows) = (quilt.as_bytes()[0] - b'0', quilt.as_bytes()[2] - b'0');
        let run = |on: &str| {
            let sub = dir.join(on);
            std::fs::create_dir_all(&sub).expect("test dir");
            quilt_in(&sub, program, quilt, "synth", &["--rows-on", on, "--log", "trace"])
        };
        let (gpu, gpu_log) = run("gpu");
        let (cpu, cpu_log) = run("cpu");
        let (g, c) = (passes(&gpu_log), passes(&cpu_log));
        assert!(g.contains(" rows ") && g.contains("resolve"), "{program}, gpu: {g}");
        assert!(
            c.contains("rows+upload") && !c.contains("resolve"),
            "{program}, cpu: {c}"
        );
        let psnr = tile_psnr(&read_png(&gpu), &read_png(&cpu), cols.into(), rows.into());
        eprintln!("{program}: cpu against gpu rows, per view {psnr:.1?}");
        assert!(
            psnr[centre].is_infinite(),
            "{program}: the rendered view differs: {psnr:.1?}"
        );
        for (v, p) in psnr.iter().enumerate() {
            assert!(
                *p >= 60.0,
                "{program} view {v}: {p:.1} dB between cpu and gpu rows ({psnr:.1?})"
            );
        }
    }
}

/// The colour uploaded straight into the tiles is the colour the resolve pass would put
/// there: with `--dump-disparity` (which reads the tiles' depth, so the resolve runs) the
/// quilt is the same, bit for bit.
#[test]
fn direct_colour_is_what_the_resolve_pass_writes() {
    require_display();
    let dir = temp_dir("rows_on_cpu_direct");
    let (direct, log) = quilt_in(
        &dir.join("direct"),
        "cubes",
        "5x1",
        "synth",
        &["--rows-on", "cpu", "--log", "trace"],
    );
    assert!(passes(&log).contains("rows+upload"), "{}", passes(&log));
    let (resolved, log) = quilt_in(
        &dir.join("resolved"),
        "cubes",
        "5x1",
        "synth",
        &["--rows-on", "cpu", "--log", "trace", "--dump-disparity"],
    );
    let p = passes(&log);
    assert!(p.contains(" rows ") && p.contains("resolve"), "{p}");
    assert_identical(&direct, &resolved);
}
