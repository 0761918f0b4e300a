//! Fragment and compute invocations per frame, asked of the driver with pipeline-statistics
//! queries (`ARB_pipeline_statistics_query`, core in 4.6; llvmpipe has it), for `--gpu-counts`.
//!
//! A query's result is read one frame after it ended, so that reading never waits for the
//! GPU: two pairs of queries take turns, and what a frame counted on the CPU travels with its
//! pair until the result is in.

use super::*;

const FRAGMENT_SHADER_INVOCATIONS: GLenum = 0x82F4;
const COMPUTE_SHADER_INVOCATIONS: GLenum = 0x82F5;

/// The two queries of one frame and what the CPU counted for it.
struct Pending<T> {
    queries: [u32; 2],
    frame: Option<T>,
}

pub struct FrameStats<T> {
    pairs: [Pending<T>; 2],
    /// The pair counting now (begun at the last boundary).
    active: Option<usize>,
    /// The pair that ended last: its result is read a boundary later.
    ended: Option<usize>,
    compute: bool,
}

/// Invocations a frame's queries counted.
#[derive(Clone, Copy, Debug)]
pub struct Invocations {
    pub fragments: u64,
    pub compute: Option<u64>,
}

impl<T> FrameStats<T> {
    /// `None` where the context has no pipeline-statistics queries.
    pub fn new(gl: &Gl, info: GlInfo) -> Option<Self> {
        if info.es || !(info.at_least(4, 6) || has_extension(gl, info, "GL_ARB_pipeline_statistics_query")) {
            return None;
        }
        if !(gl.GenQueries.is_loaded() && gl.BeginQuery.is_loaded() && gl.GetQueryObjectui64v.is_loaded()) {
            return None;
        }
        let mut names = [0u32; 4];
        // SAFETY: four names into a four-element array.
        unsafe { gl.GenQueries(4, names.as_mut_ptr()) };
        let pair = |i: usize| Pending {
            queries: [names[2 * i], names[2 * i + 1]],
            frame: None,
        };
        Some(FrameStats {
            pairs: [pair(0), pair(1)],
            active: None,
            ended: None,
            compute: info.at_least(4, 3),
        })
    }

    /// Ends the frame counting now, with what the CPU counted for it.
    pub fn end(&mut self, gl: &Gl, frame: T) {
        let Some(i) = self.active.take() else { return };
        // SAFETY: ending the queries this object began on the same context.
        unsafe {
            gl.EndQuery(FRAGMENT_SHADER_INVOCATIONS);
            if self.compute {
                gl.EndQuery(COMPUTE_SHADER_INVOCATIONS);
            }
        }
        self.pairs[i].frame = Some(frame);
        self.ended = Some(i);
    }

    /// Begins counting the next frame; returns the frame before the one just ended, with the
    /// invocations its queries counted (the GPU has had a frame to finish them).
    pub fn begin(&mut self, gl: &Gl) -> Option<(T, Invocations)> {
        let i = self.ended.map_or(0, |e| 1 - e);
        let done = self.pairs[i].frame.take().map(|frame| (frame, self.result(gl, i)));
        let q = self.pairs[i].queries;
        // SAFETY: our own query names; no query of these targets is active (ours ended).
        unsafe {
            gl.BeginQuery(FRAGMENT_SHADER_INVOCATIONS, q[0]);
            if self.compute {
                gl.BeginQuery(COMPUTE_SHADER_INVOCATIONS, q[1]);
            }
        }
        self.active = Some(i);
        done
    }

    /// Every frame whose result is still to come, waiting for the GPU (at the last frame).
    pub fn drain(&mut self, gl: &Gl) -> Vec<(T, Invocations)> {
        let order = self.ended.map_or([0, 1], |e| [1 - e, e]);
        let mut done = Vec::new();
        for i in order {
            if let Some(frame) = self.pairs[i].frame.take() {
                done.push((frame, self.result(gl, i)));
            }
        }
        done
    }

    fn result(&self, gl: &Gl, i: usize) -> Invocations {
        let q = self.pairs[i].queries;
        let read = |name: u32| {
            let mut v = 0u64;
            // SAFETY: an ended query of ours; one value into a u64.
            unsafe { gl.GetQueryObjectui64v(name, QUERY_RESULT, &mut v) };
            v
        };
        Invocations {
            fragments: read(q[0]),
            compute: self.compute.then(|| read(q[1])),
        }
    }
}

/// The extension string lists `name` (indexed strings from 3.0, the one string before).
fn has_extension(gl: &Gl, info: GlInfo, name: &str) -> bool {
    let listed = |p: *const u8| {
        // SAFETY: GL returns NUL-terminated static strings or null.
        !p.is_null() && unsafe { std::ffi::CStr::from_ptr(p.cast()) }.to_bytes() == name.as_bytes()
    };
    if info.at_least(3, 0) && gl.GetStringi.is_loaded() {
        let mut n = 0;
        // SAFETY: one integer out.
        unsafe { gl.GetIntegerv(NUM_EXTENSIONS, &mut n) };
        // SAFETY: indices below NUM_EXTENSIONS.
        return (0..n.max(0) as u32).any(|i| listed(unsafe { gl.GetStringi(EXTENSIONS, i) }));
    }
    // SAFETY: GL_EXTENSIONS is a valid name on every pre-3.0 and compatibility context.
    let all = unsafe { gl.GetString(EXTENSIONS) };
    // SAFETY: as above.
    !all.is_null()
        && unsafe { std::ffi::CStr::from_ptr(all.cast()) }
            .to_bytes()
            .split(|&b| b == b' ')
            .any(|e| e == name.as_bytes())
}
