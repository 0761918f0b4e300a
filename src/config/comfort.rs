//! The comfort effects' settings (`--depth-remap`, `--edge-fade`, `--dof`, `--comfort`) and
//! a display's comfortable range.
//!
//! All of them live in one plain struct, [`ComfortSettings`], that the layer reads every
//! frame (nothing is compiled into shaders), so they can be changed while the app runs.
//!
//! ## A display's comfortable range
//! Agus et al. give the size of the smallest feature a light-field display shows at distance
//! `z` from its screen as `s(z) = s0 + 2|z|·tan(Φ/2)`: `s0` the pixel size on the screen
//! (here one lenticule, `1/pitch` inch), `Φ` the angle between neighbouring views (the view
//! cone over the number of views). We call comfortable what is shown at most twice as coarse
//! as the screen plane, `s(z) ≤ 2·s0`, i.e. `|z| ≤ s0/(2·tan(Φ/2))`, the same in front and
//! behind, and put the asymptotes where it is four times as coarse (`3×` that depth). A
//! point at depth `z` is seen by the outermost view `z·tan(cone/2)` off the centre view's
//! point on the screen: times the DPI, times tile pixels per screen pixel, that is the range
//! in the unit of `--depth-remap`. For the Portrait (pitch 52 lenticules/inch, 40° over 48
//! views, 324 DPI, 1536-px screen, 420-px tiles) it gives 43 px, where the default
//! depthiness puts infinity at 94 px.

/// `--depth-remap F,B,DF,DB`: the comfortable range `[-F, B]` and the asymptotes `-D_F`,
/// `D_B`, as disparity of the outermost view in tile pixels (positive behind the screen).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DepthRemap {
    pub front: f64,
    pub back: f64,
    pub front_limit: f64,
    pub back_limit: f64,
    /// The tile width these are pixels of, for a display's range (its own quilt's tiles):
    /// [`DepthRemap::for_tile`] rescales it to the tiles in use, so that it keeps its depth
    /// on the display whatever `--tile` says. `None`: pixels of the tiles in use (the user's).
    pub tile_w: Option<u32>,
}

impl DepthRemap {
    /// In pixels of `tile_w`-pixel tiles.
    pub fn for_tile(self, tile_w: u32) -> DepthRemap {
        match self.tile_w {
            Some(w) if w > 0 && tile_w > 0 && w != tile_w => {
                let k = f64::from(tile_w) / f64::from(w);
                DepthRemap {
                    front: self.front * k,
                    back: self.back * k,
                    front_limit: self.front_limit * k,
                    back_limit: self.back_limit * k,
                    tile_w: Some(tile_w),
                }
            }
            _ => self,
        }
    }

    /// The same range, measured in pixels of `tile_w`-pixel tiles.
    pub fn of_tile(self, tile_w: u32) -> DepthRemap {
        DepthRemap {
            tile_w: Some(tile_w),
            ..self
        }
    }

    /// Checks `0 ≤ F < D_F` and `0 ≤ B < D_B`, all finite; `Err` is a one-line reason.
    pub fn new(front: f64, back: f64, front_limit: f64, back_limit: f64) -> Result<DepthRemap, String> {
        let all = [front, back, front_limit, back_limit];
        if !all.iter().all(|x| x.is_finite()) {
            return Err("every value must be a finite number of pixels".into());
        }
        if front < 0.0 || back < 0.0 {
            return Err("F and B (the comfortable range) must be ≥ 0".into());
        }
        if front_limit <= front || back_limit <= back {
            return Err("each limit must exceed its range: DF > F and DB > B".into());
        }
        Ok(DepthRemap {
            front,
            back,
            front_limit,
            back_limit,
            tile_w: None,
        })
    }
}

/// The comfort effects as configured; `None` is off.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ComfortSettings {
    /// `--depth-remap` (tile pixels of the outermost view's disparity).
    pub remap: Option<DepthRemap>,
    /// `--edge-fade PX`: the band at the left and right borders of each view, in tile pixels.
    pub edge_fade: Option<f64>,
    /// `--dof`: blur strength (1 = `on`): the largest blur radius is `6·STRENGTH` tile pixels.
    pub dof: Option<f64>,
    /// The range `[-F, B]` the fade and the depth of field measure from (the remap's when
    /// given, else the device's, else [`DEFAULT_RANGE`]).
    pub range: Option<DepthRemap>,
}

impl ComfortSettings {
    /// Whether a post-pass over the quilt is needed.
    pub fn post_pass(&self) -> bool {
        self.edge_fade.is_some() || self.dof.is_some()
    }

    /// The range effects measure from.
    pub fn range(&self) -> DepthRemap {
        self.range.or(self.remap).unwrap_or(DEFAULT_RANGE)
    }
}

/// Without a device: the Portrait's range (the display the default 8x6 quilt is made for),
/// in pixels of its 420-pixel tiles.
pub const DEFAULT_RANGE: DepthRemap = DepthRemap {
    front: 43.0,
    back: 43.0,
    front_limit: 129.0,
    back_limit: 129.0,
    tile_w: Some(420),
};

/// `--depth-remap F,B,DF,DB|off`.
pub fn depth_remap(v: &str) -> Result<Option<DepthRemap>, String> {
    if v.trim() == "off" {
        return Ok(None);
    }
    let parts: Vec<&str> = v.split(',').map(str::trim).collect();
    let numbers: Option<Vec<f64>> = parts.iter().map(|p| p.parse::<f64>().ok()).collect();
    match numbers.as_deref() {
        Some(&[f, b, df, db]) => DepthRemap::new(f, b, df, db)
            .map(Some)
            .map_err(|e| format!("`{v}`: {e}")),
        _ => Err(format!(
            "`{v}`: expected F,B,DF,DB (tile pixels, e.g. 40,40,120,120) or off"
        )),
    }
}

/// `--edge-fade off|PX`: a band of 1 to 10,000 tile pixels.
pub fn edge_fade(v: &str) -> Result<Option<f64>, String> {
    match v.trim() {
        "off" => Ok(None),
        x => match x.parse::<f64>() {
            Ok(px) if (1.0..=10_000.0).contains(&px) => Ok(Some(px)),
            _ => Err(format!("`{v}`: expected off or a width in tile pixels (1 to 10000)")),
        },
    }
}

/// `--dof off|on|STRENGTH`: strength in (0, 10].
pub fn dof(v: &str) -> Result<Option<f64>, String> {
    match v.trim() {
        "off" => Ok(None),
        "on" => Ok(Some(1.0)),
        x => match x.parse::<f64>() {
            Ok(s) if s > 0.0 && s <= 10.0 => Ok(Some(s)),
            _ => Err(format!("`{v}`: expected off, on or a strength in (0, 10]")),
        },
    }
}

/// `--comfort on|off`.
pub fn comfort(v: &str) -> Result<bool, String> {
    match v.trim() {
        "on" => Ok(true),
        "off" => Ok(false),
        _ => Err(format!("`{v}`: expected on or off")),
    }
}

/// The comfortable range of a display (module essay), in pixels of `tile_w`-pixel tiles of a
/// quilt of `views` views; `None` when the calibration cannot give one.
pub fn device_range(pitch: f64, dpi: f64, screen_w: u32, cone_deg: f64, views: u32, tile_w: u32) -> Option<DepthRemap> {
    let step = (cone_deg / views.max(1) as f64).to_radians();
    let depth_in = (1.0 / pitch) / (2.0 * (step / 2.0).tan());
    let px = depth_in * (cone_deg.to_radians() / 2.0).tan() * dpi * tile_w as f64 / screen_w.max(1) as f64;
    let px = px.round();
    DepthRemap::new(px, px, 3.0 * px, 3.0 * px).ok().filter(|_| px >= 1.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn values_and_errors() {
        let r = depth_remap(" 10, 20,30 ,40").unwrap().unwrap();
        assert_eq!((r.front, r.back, r.front_limit, r.back_limit), (10.0, 20.0, 30.0, 40.0));
        assert_eq!(depth_remap("off"), Ok(None));
        assert!(depth_remap("10,20,30").unwrap_err().contains("expected F,B,DF,DB"));
        assert!(depth_remap("10,20,5,40").unwrap_err().contains("DF > F"));
        assert_eq!(edge_fade("24"), Ok(Some(24.0)));
        assert!(edge_fade("-3").is_err() && edge_fade("wide").is_err());
        assert_eq!(
            (dof("on"), dof("off"), dof("2.5")),
            (Ok(Some(1.0)), Ok(None), Ok(Some(2.5)))
        );
        assert!(dof("0").is_err() && dof("NaN").is_err());
        assert!(comfort("maybe").unwrap_err().contains("on or off"));
    }

    #[test]
    fn portrait_range_is_the_documented_one() {
        let r = device_range(52.0, 324.0, 1536, 40.0, 48, 420).unwrap();
        assert_eq!(r.of_tile(420), DEFAULT_RANGE);
    }

    /// A display's range keeps its depth on the display at other tile sizes; the user's is
    /// already in the tiles in use.
    #[test]
    fn a_display_range_follows_the_tile_width() {
        let r = DEFAULT_RANGE.for_tile(210);
        assert_eq!((r.front, r.back, r.front_limit, r.back_limit), (21.5, 21.5, 64.5, 64.5));
        assert_eq!(DEFAULT_RANGE.for_tile(420), DEFAULT_RANGE);
        let user = DepthRemap::new(4.0, 4.0, 8.0, 10.0).unwrap();
        assert_eq!(user.for_tile(210), user);
    }
}
