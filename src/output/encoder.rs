//! The `--record` encoder: an `ffmpeg` child process fed raw RGBA quilts over a pipe by a
//! writer thread, so the program's thread only hands frames over.
//!
//! Why a child process: ffmpeg is the encoder every Linux user already has, it owns the
//! codec and container choices (H.264 in MP4 plays in Looking Glass Studio and browsers), and
//! a crash or stall in it cannot take the program down. Why a bounded queue: the program must
//! never wait for the encoder. When the queue is full the frame is dropped and counted (the
//! video then runs shorter than the program did); one warning says so, the summary counts.
//!
//! The rate encoded is the one measured before the start (`record`); at the end, when the
//! program's real rate over the whole recording differs by more than 1%, the file's
//! timestamps are rescaled by a stream copy (`-itsscale`, nothing encoded again), so the
//! video lasts as long as the program ran. A run killed before the end keeps the first rate.
//! x264's `ultrafast` preset: the encoder shares the machine with the program it records.
//!
//! ffmpeg gets its own process group (Ctrl-C at the program must not kill it before it wrote
//! the MP4 index: it finishes on the pipe's end instead), no `LD_PRELOAD` (the layer has no
//! business in it), no stdin but the pipe and no stdout.

use std::io::Write;
use std::os::unix::process::CommandExt;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::sync::mpsc::{Receiver, SyncSender, TrySendError, sync_channel};
use std::thread::JoinHandle;
use std::time::Instant;

/// Bytes of frames waiting for the writer at most (at least 2 frames, at most 16).
const QUEUE_BYTES: usize = 256 << 20;

/// One frame: RGBA rows bottom-up (as GL reads them), in the conventional tile order.
pub type Frame = Vec<u8>;

pub struct Encoder {
    pub path: PathBuf,
    pub size: (u32, u32),
    pub fps: f64,
    tx: Option<SyncSender<Frame>>,
    writer: Option<JoinHandle<Result<u64, String>>>,
    child: Child,
    pub sent: u64,
    pub dropped: u64,
    /// When the first and the last frame were handed over (sent or dropped).
    span: Option<(Instant, Instant)>,
}

/// `ffmpeg` as found in `PATH`, or why not.
pub fn find_ffmpeg() -> Result<PathBuf, String> {
    let path = std::env::var_os("PATH").unwrap_or_default();
    std::env::split_paths(&path)
        .map(|d| d.join("ffmpeg"))
        .find(|p| p.is_file())
        .ok_or_else(|| "no encoder: `ffmpeg` is not in PATH (Debian/Ubuntu: apt install ffmpeg)".to_string())
}

/// The ffmpeg arguments: raw RGBA in, rows flipped to top-down, padded to even sizes at the
/// top and right (4:2:0 needs them; the bottom-left tile origin stays put), H.264 out.
pub fn ffmpeg_args(out: &Path, size: (u32, u32), fps: f64) -> Vec<String> {
    let rate = format!("{}/1000", (fps * 1000.0).round().max(1.0) as u64);
    let s = |v: &str| v.to_string();
    vec![
        s("-hide_banner"),
        s("-loglevel"),
        s("error"),
        s("-y"),
        s("-f"),
        s("rawvideo"),
        s("-pix_fmt"),
        s("rgba"),
        s("-s"),
        format!("{}x{}", size.0, size.1),
        s("-framerate"),
        rate,
        s("-i"),
        s("-"),
        s("-vf"),
        s("vflip,pad=ceil(iw/2)*2:ceil(ih/2)*2:0:oh-ih"),
        s("-c:v"),
        s("libx264"),
        s("-preset"),
        s("ultrafast"),
        s("-crf"),
        s("18"),
        s("-pix_fmt"),
        s("yuv420p"),
        s("-movflags"),
        s("+faststart"),
        out.to_string_lossy().into_owned(),
    ]
}

impl Encoder {
    pub fn start(path: &Path, size: (u32, u32), fps: f64) -> Result<Encoder, String> {
        let ffmpeg = find_ffmpeg()?;
        let mut child = Command::new(&ffmpeg)
            .args(ffmpeg_args(path, size, fps))
            .stdin(Stdio::piped())
            .stdout(Stdio::null())
            .stderr(Stdio::inherit())
            .env_remove("LD_PRELOAD")
            .process_group(0)
            .spawn()
            .map_err(|e| format!("cannot start {}: {e}", ffmpeg.display()))?;
        let stdin = child.stdin.take().ok_or("ffmpeg has no stdin pipe")?;
        let frame_bytes = size.0 as usize * size.1 as usize * 4;
        let (tx, rx) = sync_channel((QUEUE_BYTES / frame_bytes.max(1)).clamp(2, 16));
        let writer = std::thread::Builder::new()
            .name("holoinject-record".into())
            .spawn(move || write_frames(rx, stdin))
            .map_err(|e| format!("cannot start the writer thread: {e}"))?;
        Ok(Encoder {
            path: path.to_path_buf(),
            size,
            fps,
            tx: Some(tx),
            writer: Some(writer),
            child,
            sent: 0,
            dropped: 0,
            span: None,
        })
    }

    /// Queues a frame without waiting (unless `wait`); `Ok(false)`: dropped (the encoder is
    /// behind).
    pub fn push(&mut self, frame: Frame, wait: bool) -> Result<bool, String> {
        let tx = self.tx.as_ref().ok_or("the recording has ended")?;
        let now = Instant::now();
        self.span = Some((self.span.map_or(now, |s| s.0), now));
        let sent = if wait {
            tx.send(frame).map_err(|e| TrySendError::Disconnected(e.0))
        } else {
            tx.try_send(frame)
        };
        match sent {
            Ok(()) => {
                self.sent += 1;
                Ok(true)
            }
            Err(TrySendError::Full(_)) => {
                self.dropped += 1;
                Ok(false)
            }
            Err(TrySendError::Disconnected(_)) => Err(self.writer_error()),
        }
    }

    fn writer_error(&mut self) -> String {
        self.tx = None;
        match self.writer.take().map(|w| w.join()) {
            Some(Ok(Err(e))) => e,
            _ => "the encoder stopped".into(),
        }
    }

    /// Writes what is queued, closes the pipe and waits for ffmpeg to finish the file;
    /// returns how many frames it received and the file's frame rate.
    pub fn finish(mut self) -> Result<(u64, f64), String> {
        self.tx = None;
        let written = match self.writer.take().map(|w| w.join()) {
            Some(Ok(r)) => r,
            _ => Err("the writer thread panicked".into()),
        };
        let status = self.child.wait().map_err(|e| format!("ffmpeg: {e}"))?;
        if !status.success() {
            return Err(format!("ffmpeg ended with {status}"));
        }
        let written = written?;
        if let Some(fps) = self.real_fps(written) {
            self.fps = retime(&self.path, self.fps, fps)?;
        }
        Ok((written, self.fps))
    }

    /// The rate at which `written` frames last as long as the program took to make them, when
    /// it differs by more than 1% from the rate encoded (measured at the start).
    fn real_fps(&self, written: u64) -> Option<f64> {
        let (first, last) = self.span?;
        let captured = self.sent + self.dropped;
        let secs = (last - first).as_secs_f64();
        if captured < 2 || written == 0 || secs <= 0.0 {
            return None;
        }
        // `captured - 1` intervals span `secs`; the video shows `written` frames in that time
        // plus one interval.
        let fps = written as f64 * (captured - 1) as f64 / (secs * captured as f64);
        ((fps / self.fps - 1.0).abs() > 0.01).then_some(fps)
    }
}

/// Rewrites `path`'s timestamps for `fps` (a stream copy: nothing is encoded again); returns
/// the rate the file now has.
fn retime(path: &Path, encoded: f64, fps: f64) -> Result<f64, String> {
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    let tmp = path.with_file_name(format!(".retime-{name}"));
    let status = Command::new(find_ffmpeg()?)
        .args(["-hide_banner", "-loglevel", "error", "-y", "-itsscale"])
        .arg(format!("{}", encoded / fps))
        .arg("-i")
        .arg(path)
        .args(["-c", "copy", "-movflags", "+faststart"])
        .arg(&tmp)
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .env_remove("LD_PRELOAD")
        .status()
        .map_err(|e| format!("ffmpeg (re-timing): {e}"))?;
    if !status.success() {
        let _ = std::fs::remove_file(&tmp);
        return Err(format!(
            "re-timing to {fps:.2} fps failed ({status}); the file keeps {encoded:.2} fps"
        ));
    }
    std::fs::rename(&tmp, path).map_err(|e| format!("{}: {e}", path.display()))?;
    Ok(fps)
}

fn write_frames(rx: Receiver<Frame>, mut stdin: std::process::ChildStdin) -> Result<u64, String> {
    let mut n = 0;
    for frame in rx {
        stdin
            .write_all(&frame)
            .map_err(|e| format!("writing frame {} to ffmpeg: {e}", n + 1))?;
        n += 1;
    }
    Ok(n)
}

#[cfg(test)]
mod tests {
    #[test]
    fn odd_sizes_are_padded_at_the_top_and_rates_are_exact_fractions() {
        let a = super::ffmpeg_args(std::path::Path::new("/v/x.mp4"), (801, 601), 59.94);
        assert!(a.windows(2).any(|w| w == ["-framerate", "59940/1000"]), "{a:?}");
        assert!(a.windows(2).any(|w| w == ["-s", "801x601"]), "{a:?}");
        assert_eq!(a.last().map(String::as_str), Some("/v/x.mp4"));
    }
}
