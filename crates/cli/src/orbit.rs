//! `spreadlight bench --orbit ID.PIN=RADIANS`: a Vec3 pin (a camera's
//! position, say a LookAt's) turned about the world's vertical axis by
//! RADIANS more every frame, so a still patch is timed with a moving camera:
//! what sun cascades following the camera cost (docs/shadows.md, "Cascades
//! that scroll").

use anyhow::{Context, bail};
use spreadlight_graph::{NodeId, Patch, PinType, Spread};

use crate::pin_arg::PinArg;

/// The pin turned, where it started and how far it turns a frame.
pub struct Orbit {
    node: NodeId,
    pin: String,
    start: Vec<glam::Vec3>,
    radians: f32,
}

impl Orbit {
    /// `ID.PIN=RADIANS`, checked against `patch`: the node must exist and the pin be a Vec3 input.
    pub fn parse(patch: &Patch, text: &str) -> anyhow::Result<Orbit> {
        let PinArg {
            node: id,
            pin,
            value,
            ty,
        } = PinArg::parse(patch, "orbit", "RADIANS", text)?;
        let radians: f32 = value
            .trim()
            .parse()
            .ok()
            .filter(|r: &f32| r.is_finite())
            .with_context(|| format!("`--orbit {text}`: `{value}` is not a number of radians"))?;
        if ty != PinType::Vec3 {
            bail!(
                "`--orbit {text}`: input `{pin}` of node #{} is a {ty}, not a Vec3",
                id.0
            );
        }
        let node = patch
            .node(id)
            .with_context(|| format!("`--orbit {text}`: no node #{}", id.0))?;
        let start = match node.values.get(pin) {
            Some(Spread::Vec3(v)) if !v.is_empty() => v.clone(),
            _ => {
                bail!(
                    "`--orbit {text}`: input `{pin}` of node #{} has no value set in the patch",
                    id.0
                )
            }
        };
        Ok(Orbit {
            node: id,
            pin: pin.to_owned(),
            start,
            radians,
        })
    }

    /// Set the pin to where it stands at `frame` (turned `frame` times).
    pub fn place(&self, patch: &mut Patch, frame: u64) {
        let turn = glam::Quat::from_rotation_y((frame as f64 * f64::from(self.radians)) as f32);
        if let Some(node) = patch.node_mut(self.node) {
            let turned = self.start.iter().map(|&p| turn * p).collect();
            node.values.insert(self.pin.clone(), Spread::Vec3(turned));
        }
    }
}
