//! Where control sockets live: `$XDG_RUNTIME_DIR/holoinject/PID.sock`. Without
//! `$XDG_RUNTIME_DIR` (a bare `su`, cron, some containers), `/tmp/holoinject-UID`: created
//! mode 0700, and used only when it is a real directory (not a symlink) of this user that
//! no one else can enter; anything else there is refused, so another user cannot plant a
//! directory or a link for us.

use std::os::unix::fs::{DirBuilderExt, MetadataExt, PermissionsExt};
use std::path::{Path, PathBuf};

pub fn uid() -> u32 {
    // SAFETY: geteuid cannot fail.
    unsafe { libc::geteuid() }
}

/// The socket directory for this user, and how it was chosen (for messages).
pub fn socket_dir(env: &dyn Fn(&str) -> Option<String>) -> (PathBuf, String) {
    match env("XDG_RUNTIME_DIR").filter(|d| d.starts_with('/')) {
        Some(d) => (Path::new(&d).join("holoinject"), "$XDG_RUNTIME_DIR".into()),
        None => (
            PathBuf::from(format!("/tmp/holoinject-{}", uid())),
            "XDG_RUNTIME_DIR is not set: fallback".into(),
        ),
    }
}

pub fn socket_path(dir: &Path, pid: u32) -> PathBuf {
    dir.join(format!("{pid}.sock"))
}

/// Creates `dir` (mode 0700) when missing and checks it is private to this user.
pub fn ensure_private_dir(dir: &Path) -> Result<(), String> {
    if let Err(e) = std::fs::DirBuilder::new().mode(0o700).create(dir)
        && e.kind() != std::io::ErrorKind::AlreadyExists
    {
        return Err(format!("{}: cannot create: {e}", dir.display()));
    }
    check_private_dir(dir)
}

pub fn check_private_dir(dir: &Path) -> Result<(), String> {
    let m = std::fs::symlink_metadata(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    if !m.file_type().is_dir() {
        return Err(format!("{}: not a directory (a link?); refused", dir.display()));
    }
    if m.uid() != uid() {
        return Err(format!(
            "{}: owned by uid {}, not {}; refused",
            dir.display(),
            m.uid(),
            uid()
        ));
    }
    if m.permissions().mode() & 0o077 != 0 {
        return Err(format!(
            "{}: mode {:o} lets others in (expected 700); refused",
            dir.display(),
            m.permissions().mode() & 0o777
        ));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_directory_must_be_private() {
        let base = std::env::temp_dir().join(format!("holoinject-paths-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&base);
        std::fs::create_dir_all(&base).unwrap();
        let dir = base.join("holoinject");
        ensure_private_dir(&dir).unwrap();
        assert_eq!(std::fs::metadata(&dir).unwrap().permissions().mode() & 0o777, 0o700);
        std::fs::set_permissions(&dir, std::fs::Permissions::from_mode(0o755)).unwrap();
        assert!(
            ensure_private_dir(&dir)
                .unwrap_err()
                .contains("mode 755 lets others in")
        );
        let link = base.join("link");
        std::os::unix::fs::symlink(&dir, &link).unwrap();
        assert!(check_private_dir(&link).unwrap_err().contains("not a directory"));
        std::fs::remove_dir_all(&base).unwrap();
    }

    #[test]
    fn without_a_runtime_dir_the_fallback_names_the_user() {
        let (dir, why) = socket_dir(&|_| None);
        assert_eq!(dir, PathBuf::from(format!("/tmp/holoinject-{}", uid())));
        assert!(why.contains("XDG_RUNTIME_DIR is not set"));
        let (dir, _) = socket_dir(&|k| (k == "XDG_RUNTIME_DIR").then(|| "/run/user/5".into()));
        assert_eq!(dir, PathBuf::from("/run/user/5/holoinject"));
    }
}
