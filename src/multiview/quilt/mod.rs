//! The quilt standing in for the app's window: where each view lives (`layout`), the render
//! target made like the real default framebuffer (`target`, `window_format`), and how many
//! tile pixels a unit of parallax is in the tiles in use (`comfort`).
//!
//! The bottom room: it names no other room.

pub mod comfort;
pub mod layout;
pub mod record;
pub mod target;
pub mod window_format;
