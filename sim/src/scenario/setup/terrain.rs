//! Validates `[terrain]`: the base sideslip angles and the slip patches.

use fieldguide::model::bicycle::Sideslip;

use crate::error::ScenarioError;
use crate::scenario::check::Checker;
use crate::scenario::schema::ScenarioFile;
use crate::world::terrain::{Ground, SlipPatch, Terrain, Undulation};

/// The front and rear sideslip angles `{prefix}front_sideslip_deg` and
/// `{prefix}rear_sideslip_deg`, each within ±45°.
fn sideslip(
    check: &Checker<'_>,
    prefix: &str,
    front_deg: f64,
    rear_deg: f64,
) -> Result<Sideslip, ScenarioError> {
    let front = check.range(
        &format!("{prefix}front_sideslip_deg"),
        front_deg,
        -45.0,
        45.0,
    )?;
    let rear = check.range(&format!("{prefix}rear_sideslip_deg"), rear_deg, -45.0, 45.0)?;
    Sideslip::new(front.to_radians(), rear.to_radians())
        .map_err(|e| check.error(&format!("{prefix}front_sideslip_deg"), &e.to_string()))
}

/// The terrain of `[terrain]`: its base sideslip and its patches.
pub(super) fn terrain(file: &ScenarioFile, check: &Checker<'_>) -> Result<Terrain, ScenarioError> {
    let t = &file.terrain;
    let base = sideslip(check, "terrain.", t.front_sideslip_deg, t.rear_sideslip_deg)?;
    let mut patches = Vec::with_capacity(t.patches.len());
    for (i, p) in t.patches.iter().enumerate() {
        let prefix = format!("terrain.patches[{i}].");
        if p.polygon.len() < 3 {
            return Err(check.error(&format!("{prefix}polygon"), "needs at least 3 vertices"));
        }
        for (k, v) in p.polygon.iter().enumerate() {
            check.finite(&format!("{prefix}polygon[{k}][0]"), v[0])?;
            check.finite(&format!("{prefix}polygon[{k}][1]"), v[1])?;
        }
        patches.push(SlipPatch {
            name: p.name.clone(),
            polygon: p.polygon.clone(),
            sideslip: sideslip(check, &prefix, p.front_sideslip_deg, p.rear_sideslip_deg)?,
        });
    }
    Ok(Terrain {
        base,
        patches,
        ground: ground(file, check)?,
    })
}

/// The ground's shape of `[terrain]`: slopes within ±100 %, an undulation
/// of amplitude below 5 m and a wavelength of at least 1 m.
fn ground(file: &ScenarioFile, check: &Checker<'_>) -> Result<Ground, ScenarioError> {
    let t = &file.terrain;
    let slope = [
        check.range("terrain.slope_x_percent", t.slope_x_percent, -100.0, 100.0)? / 100.0,
        check.range("terrain.slope_y_percent", t.slope_y_percent, -100.0, 100.0)? / 100.0,
    ];
    let amplitude = check.range(
        "terrain.undulation_amplitude_m",
        t.undulation_amplitude_m,
        0.0,
        5.0,
    )?;
    let heading = check.range(
        "terrain.undulation_heading_deg",
        t.undulation_heading_deg,
        -360.0,
        360.0,
    )?;
    let undulation = match (amplitude > 0.0, t.undulation_wavelength_m) {
        (false, None) => None,
        (false, Some(_)) => {
            return Err(check.error(
                "terrain.undulation_wavelength_m",
                "an undulation needs undulation_amplitude_m > 0",
            ))
        }
        (true, None) => {
            return Err(check.error(
                "terrain.undulation_wavelength_m",
                "needed with undulation_amplitude_m",
            ))
        }
        (true, Some(w)) => Some(Undulation {
            amplitude,
            wavelength: check.range("terrain.undulation_wavelength_m", w, 1.0, 1e4)?,
            heading: heading.to_radians(),
        }),
    };
    Ok(Ground { slope, undulation })
}
