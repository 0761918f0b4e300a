//! `--gpu-counts` at the frame boundary: the frame's CPU counters are taken and its
//! statistics queries ended before the present, the next frame's begun after it (so the
//! layer's compose, weave and dumps count, the swap itself does not). Frames are kept for the
//! summary as `output::timing` keeps them: after the warm-up, not the measured ones.

use crate::log::counts::{self, FrameCounts};

/// Before the present of `frame`.
pub fn end_frame(frame: u64, measured: bool) {
    if !crate::config::settings().gpu_counts {
        return;
    }
    let mut c = counts::take();
    let keep = frame > crate::output::timing::WARM_UP && !measured;
    let kept = super::layer::with_layer(|_, _, layer, gl| {
        c.tile_pixels = layer
            .views
            .layout()
            .map_or(0, |l| u64::from(l.tile_w) * u64::from(l.tile_h));
        let stats = layer.gpu_stats.get_or_insert_with(|| {
            let s = crate::gl::stats_query::FrameStats::new(gl, layer.views.info);
            if s.is_none() {
                crate::log::info(format_args!(
                    "gpu-counts: no pipeline-statistics queries here; fragments not counted"
                ));
            }
            s
        });
        match stats {
            Some(s) => s.end(gl, FrameCounts { keep, ..c }),
            None if keep => counts::keep(c),
            None => {}
        }
    });
    if kept.is_none() && keep {
        counts::keep(c);
    }
}

/// After the present of `frame`: the next frame's queries begin, and the frame before the
/// one just ended gets its invocations; after the last frame (`--exit-after`) every pending
/// frame gets them.
pub fn begin_frame(frame: u64) {
    let settings = crate::config::settings();
    if !settings.gpu_counts {
        return;
    }
    let last = settings.exit_after == Some(frame);
    super::layer::with_layer(|_, _, layer, gl| {
        let Some(Some(stats)) = &mut layer.gpu_stats else {
            return;
        };
        let done = if last {
            stats.drain(gl)
        } else {
            stats.begin(gl).into_iter().collect()
        };
        for (c, inv) in done.into_iter().filter(|(c, _)| c.keep) {
            counts::keep(FrameCounts {
                fragments: Some(inv.fragments),
                compute: inv.compute,
                ..c
            });
        }
    });
}
