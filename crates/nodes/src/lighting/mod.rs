//! Lights and shading nodes (category "Lighting"): `AddLight (Point)`,
//! `AddLight (Spot)`, `AddLight (Sun)`, `PointLightBuffer`,
//! `SpotLightBuffer`, `SunLightBuffer`, `ShadowMap (Spot)`, `ShadowMap (Point)`,
//! `ShadowMap (Sun)`, `CookTorrance`, `CompositeLight`, `SSAO`, `HBAO`, `SSGI`, `SSSS`.

pub mod add_light;
pub mod composite_light;
pub mod cook_torrance;
pub mod point_light_buffer;
pub mod shadow_map;
pub mod spot_light_buffer;
pub mod ssao;
pub mod ssgi;
pub mod ssss;
pub mod sun_light_buffer;

use spreadlight_graph::typed_pins::InputPin;
use spreadlight_graph::{EvalContext, NodeError, Registry};

/// A NaN or infinity on `pin` is an error on the node naming the pin and
/// slice: user maths that blew up never reaches a light buffer.
pub(crate) fn require_finite(cx: &EvalContext<'_>, pin: impl InputPin) -> Result<(), NodeError> {
    if let Some(slice) = cx.spread(pin).first_non_finite() {
        return Err(cx.error(pin, format!("slice {slice} is NaN or infinite")));
    }
    Ok(())
}

pub const CATEGORY: &str = "Lighting";

pub fn register(r: &mut Registry) {
    add_light::register(r);
    point_light_buffer::register(r);
    spot_light_buffer::register(r);
    sun_light_buffer::register(r);
    shadow_map::register(r);
    cook_torrance::register(r);
    composite_light::register(r);
    ssao::register(r);
    ssgi::register(r);
    ssss::register(r);
}

#[cfg(test)]
mod tests;
