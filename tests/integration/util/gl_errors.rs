//! GL errors a replay reported on stderr, to check that the layer adds none.
//!
//! glretrace calls `glGetError` after every call it replays and reports what it finds as
//! `2546: warning: glGetError(glDrawArrays) = GL_INVALID_OPERATION`; with KHR_debug it also
//! relays the driver's messages, the errors among them as
//! `2546: message: major api error 1: GL_INVALID_OPERATION in glBlitNamedFramebuffer(…)`
//! (severity, source, type, id). An error the layer raises inside a replayed call shows up
//! at that call, but one raised and cleared by the layer itself, or raised where the program
//! makes no call, never reaches glretrace: with `MESA_DEBUG=1` (`MESA_DEBUG_ENV`), Mesa
//! prints every error as it is raised, `Mesa: User error: GL_INVALID_OPERATION in …`.

/// Makes Mesa report every GL error on stderr; nothing else changes (no flag is named "1").
pub const MESA_DEBUG_ENV: (&str, &str) = ("MESA_DEBUG", "1");

/// The lines of `stderr` that report a GL error, without the process's own noise.
pub fn gl_error_lines(stderr: &str) -> Vec<&str> {
    stderr.lines().filter(|l| is_gl_error(l)).collect()
}

fn is_gl_error(line: &str) -> bool {
    if line.contains("glGetError(") || line.starts_with("Mesa: User error") {
        return true;
    }
    // `N: message: SEVERITY SOURCE... TYPE ID: text`: the type is the word before the id.
    let Some((_, rest)) = line.split_once(": message: ") else {
        return false;
    };
    let Some((head, _)) = rest.split_once(':') else {
        return false;
    };
    let words: Vec<&str> = head.split_whitespace().collect();
    words.len() >= 2 && words[words.len() - 2] == "error"
}

/// Every GL error under the layer (`with`) is one the program's plain replay (`without`) also
/// reported: glretrace's lines name the call, so the same line means the same error at the
/// same call. Compared as sets: a draw the layer replays per view repeats the program's own
/// errors, and the plain replay may run further than the layer's (`--exit-after`). Prints
/// both counts.
pub fn assert_no_added_gl_errors(without: &str, with: &str, what: &str) {
    let (plain, layer) = (gl_error_lines(without), gl_error_lines(with));
    eprintln!(
        "{what}: GL errors reported: {} without the layer, {} with it",
        plain.len(),
        layer.len()
    );
    let added: Vec<&str> = layer.iter().copied().filter(|l| !plain.contains(l)).collect();
    assert!(
        added.is_empty(),
        "{what}: the layer adds {} GL error(s):\n{}",
        added.len(),
        added.join("\n")
    );
}

#[cfg(test)]
mod tests {
    use super::*;

    /// What glretrace and Mesa printed on this machine (the refract replay before the fix).
    #[test]
    fn recognises_what_glretrace_and_mesa_print() {
        let err = "/usr/bin/glmark2\n\
            2546: message: major api error 1: GL_INVALID_OPERATION in glBlitNamedFramebuffer(depth attachment format mismatch)\n\
            2546: warning: glGetError(glDrawArrays) = GL_INVALID_OPERATION\n\
            12: message: minor api performance issue 3: copying a texture\n\
            Mesa: User error: GL_INVALID_OPERATION in glGetFramebufferAttachmentParameteriv(invalid pname)\n\
            holoinject: info: auto-convergence: scene at 3.0\n";
        assert_eq!(gl_error_lines(err).len(), 3);
        assert_eq!(gl_error_lines("renderableType = 4\n").len(), 0);
    }

    #[test]
    #[should_panic(expected = "adds 1 GL error")]
    fn an_added_error_fails() {
        let plain = "5: warning: glGetError(glClear) = GL_INVALID_VALUE\n";
        let layer = "5: warning: glGetError(glClear) = GL_INVALID_VALUE\n9: warning: glGetError(glDrawArrays) = GL_INVALID_OPERATION\n";
        assert_no_added_gl_errors(plain, layer, "test");
    }

    #[test]
    fn the_programs_own_errors_are_not_the_layers() {
        let plain = "5: warning: glGetError(glClear) = GL_INVALID_VALUE\n";
        assert_no_added_gl_errors(plain, &plain.repeat(5), "test");
    }
}
