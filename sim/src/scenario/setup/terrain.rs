//! Validates `[terrain]`: the base sideslip angles and the slip patches.

use fieldguide::model::bicycle::Sideslip;

use crate::error::ScenarioError;
use crate::scenario::check::Checker;
use crate::scenario::schema::ScenarioFile;
use crate::world::terrain::{SlipPatch, Terrain};

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
    Ok(Terrain { base, patches })
}
