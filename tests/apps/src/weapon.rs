//! `--weapon none|plain|hack|glass|ghost` (cubes, legacy; `glass` and `ghost` legacy only): a
//! first-person "weapon", a box held before the eye and drawn last in eye space; `hack` draws
//! it inside `glDepthRange(0, 0.3)`, as id Tech 3 games draw theirs so that it never pokes
//! into a wall. Exact mode shifts it by its real distance; only a disparity read back from
//! depth takes it for a nearer one. `glass` (alpha 0.4) and `ghost` (alpha 0: a sprite faded
//! out) draw it blended without depth writes and back faces culled, as games draw
//! translucent meshes, sprites and particles: through glass a viewer sees the box, through a
//! ghost only the scene.

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Weapon {
    None,
    Plain,
    Hack,
    Glass,
    Ghost,
}

/// The option's entry for `AppInfo::extra`.
pub const OPTION: (&str, &str, &str) = (
    "weapon",
    "none",
    "none | plain | hack | glass | ghost: a box held before the eye, drawn last (hack: in \
     glDepthRange(0, 0.3); glass, ghost: blended at alpha 0.4, 0 without depth writes, legacy only)",
);

pub fn parse(value: &str) -> Result<Weapon, String> {
    match value {
        "none" => Ok(Weapon::None),
        "plain" => Ok(Weapon::Plain),
        "hack" => Ok(Weapon::Hack),
        "glass" => Ok(Weapon::Glass),
        "ghost" => Ok(Weapon::Ghost),
        w => Err(format!("--weapon: expected none|plain|hack|glass|ghost, got '{w}'")),
    }
}

/// Where the box is held, in eye space: centre and half extents (1.4 to 3 units away).
pub const CENTRE: [f32; 3] = [0.9, -0.7, -2.2];
pub const HALF: [f32; 3] = [0.25, 0.2, 0.8];

/// The depth range to draw it in.
pub fn depth_range(w: Weapon) -> (f64, f64) {
    if w == Weapon::Hack { (0.0, 0.3) } else { (0.0, 1.0) }
}

/// The alpha it is blended with (`None`: opaque, with depth writes).
pub fn alpha(w: Weapon) -> Option<f32> {
    match w {
        Weapon::Glass => Some(0.4),
        Weapon::Ghost => Some(0.0),
        _ => None,
    }
}
