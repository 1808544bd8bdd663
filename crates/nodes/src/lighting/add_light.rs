//! `AddLight (Point)`, `AddLight (Spot)`, `AddLight (Sun)`: Emeshe's way of
//! filling a light buffer. Each adds a spread of lights, one per slice, each
//! under a unique ID string, to the lights arriving at its Lights pin, so
//! nodes chain: `AddLight -> AddLight -> PointLightBuffer`. IDs do not order
//! the buffer (lights keep their order along the chain); they name lights,
//! for errors. Shadow Slice says which slice of the `ShadowMap` node of the
//! light's type holds its shadow (-1: it casts none).
//!
//! A NaN or infinity on a pin is an error on this node that names the pin
//! and slice; it never reaches a light buffer.

use std::collections::HashMap;
use std::sync::Arc;

use glam::{Mat4, Vec3};
use spreadlight_graph::spread::{cycled, slice_count};
use spreadlight_graph::{
    Color, EvalContext, In, NodeDef, NodeError, Out, Pins, Registry, Res, ResourceKind,
};
use spreadlight_render::lighting::{PointLight, SpotLight, SunLight};

use super::require_finite;

/// Lights of one type with their IDs, in order: what travels between `AddLight` nodes.
#[derive(Debug, Default)]
pub struct LightList<T> {
    pub ids: Vec<String>,
    pub lights: Vec<T>,
}

/// A pin of light lists of one type.
pub type LightsPin<T> = In<Res<LightList<T>>>;

impl<T: Clone + Send + Sync + 'static> LightList<T> {
    /// Every list arriving at `pin`, joined in slice order. An ID given twice
    /// is an error on `pin` naming it.
    pub fn gather(cx: &EvalContext<'_>, pin: LightsPin<T>) -> Result<LightList<T>, NodeError> {
        let mut all = LightList {
            ids: Vec::new(),
            lights: Vec::new(),
        };
        for list in cx.resources(pin)? {
            all.ids.extend(list.ids.iter().cloned());
            all.lights.extend(list.lights.iter().cloned());
        }
        if let Some(id) = first_duplicate(&all.ids) {
            return Err(cx.error(pin, format!("light ID `{id}` arrives twice")));
        }
        Ok(all)
    }

    /// The input of lights of `kind` that AddLight, the light buffers and
    /// the shadow maps take.
    pub fn input(p: &mut Pins<'_>, kind: ResourceKind) -> LightsPin<T> {
        p.input_resource::<LightList<T>>("Lights", kind)
    }
}

fn first_duplicate(ids: &[String]) -> Option<&str> {
    let mut seen = HashMap::with_capacity(ids.len());
    ids.iter()
        .find(|id| seen.insert(id.as_str(), ()).is_some())
        .map(String::as_str)
}

/// The ID of each of `n` lights: the ID pin's slices as they are when there
/// are as many (the pin counts in `n`, so never more), else each with the
/// round it is repeated in (`spot0`, `spot1`, ...), so one ID names a whole
/// spread uniquely.
fn light_ids(ids: &[String], n: usize) -> Vec<String> {
    if ids.is_empty() {
        return (0..n).map(|i| i.to_string()).collect();
    }
    if ids.len() >= n {
        return ids[..n].to_vec();
    }
    (0..n)
        .map(|i| format!("{}{}", ids[i % ids.len()], i / ids.len()))
        .collect()
}

/// The pins every AddLight starts with (the lights to add to, and the IDs)
/// and its output.
struct Chain<T: Send + Sync + 'static> {
    lights: LightsPin<T>,
    ids: In<String>,
    out: Out<Res<LightList<T>>>,
}

// By hand: a derive would ask `T: Copy`, and only the handles are copied.
impl<T: Send + Sync + 'static> Clone for Chain<T> {
    fn clone(&self) -> Self {
        *self
    }
}
impl<T: Send + Sync + 'static> Copy for Chain<T> {}

impl<T: Clone + Send + Sync + 'static> Chain<T> {
    fn declare(p: &mut Pins<'_>, name: &str, kind: ResourceKind) -> Self {
        let lights = LightList::input(p, kind);
        let ids = p.input(
            "ID",
            name.trim_start_matches("AddLight (")
                .trim_end_matches(')')
                .to_lowercase(),
        );
        let out = p.output_resource::<LightList<T>>("Lights", kind);
        Chain { lights, ids, out }
    }

    /// The ID pin's slice count: like every pin, it spreads the node.
    fn id_count(self, cx: &EvalContext<'_>) -> Result<usize, NodeError> {
        Ok(cx.get(self.ids)?.len())
    }

    /// The upstream lights plus `lights` under the node's IDs, as its output.
    fn add(self, cx: &mut EvalContext<'_>, lights: Vec<T>) -> Result<(), NodeError> {
        let mut list = LightList::<T>::gather(cx, self.lights)?;
        let upstream = list.ids.len();
        let ids = light_ids(cx.get(self.ids)?, lights.len());
        if let Some(id) = ids.iter().find(|id| list.ids.contains(id)) {
            return Err(cx.error(
                self.ids,
                format!("light ID `{id}` is already in the lights arriving at Lights"),
            ));
        }
        list.ids.extend(ids);
        list.lights.extend(lights);
        if let Some(id) = first_duplicate(&list.ids[upstream..]) {
            return Err(cx.error(self.ids, format!("light ID `{id}` is given twice")));
        }
        cx.put_resources(self.out, vec![Arc::new(list)]);
        Ok(())
    }
}

pub fn register(r: &mut Registry) {
    let name = "AddLight (Point)";
    r.add(
        NodeDef::new(
            name,
            super::CATEGORY,
            "Adds point lights, one per slice, to the lights at Lights: position, linear colour, \
             luminous intensity in candela (a power in lumens divided by 4 pi) and range, where the \
             light fades smoothly to zero. ID names each light (one ID for a spread: point0, point1, ...).",
        )
        .with_pins(|p| {
            let chain = Chain::<PointLight>::declare(p, name, ResourceKind::PointLights);
            let position = p.input("Position", Vec3::new(0.0, 2.0, 0.0));
            let color = p.input("Color", Color::WHITE);
            let intensity = p.input("Intensity", 100.0f32);
            let range = p.input("Range", 10.0f32);
            let shadow = p.input(SHADOW_SLICE, -1i64);
            move |cx| {
                require_finite(cx, position)?;
                require_finite(cx, color)?;
                require_finite(cx, intensity)?;
                require_finite(cx, range)?;
                let shadows = cx.get(shadow)?.to_vec();
                let (positions, colors) = (cx.get(position)?, cx.get(color)?);
                let (intensities, ranges) = (cx.get(intensity)?, cx.get(range)?);
                let n = slice_count([
                    chain.id_count(cx)?,
                    positions.len(),
                    colors.len(),
                    intensities.len(),
                    ranges.len(),
                    shadows.len(),
                ]);
                let lights: Vec<PointLight> = cycled(positions, n)
                    .zip(cycled(colors, n))
                    .zip(cycled(intensities, n))
                    .zip(cycled(ranges, n))
                    .enumerate()
                    .map(|(i, (((position, color), intensity), range))| PointLight {
                        shadow: shadow_slice(&shadows, i),
                        position: *position,
                        color: rgb(color),
                        intensity: *intensity,
                        range: *range,
                    })
                    .collect();
                chain.add(cx, lights)
            }
        }),
    );
    let name = "AddLight (Spot)";
    r.add(
        NodeDef::new(
            name,
            super::CATEGORY,
            "Adds spot lights, one per slice: projectors placed by a View transform (the light looks \
             down its -Z; LookAt (Transform) makes one) and shaped by a Projection (Perspective \
             (Transform)): the frustum is the lit volume and its far plane the range. Texture ID \
             picks the layer of the SpotLightBuffer's texture array to project (-1: a round cone \
             whose edge fades over Softness, 0..1 of its radius). Linear colour, luminous intensity in candela.",
        )
        .with_pins(|p| {
            let chain = Chain::<SpotLight>::declare(p, name, ResourceKind::SpotLights);
            let view = p.input(
                "View",
                glam::camera::rh::view::look_to_mat4(Vec3::new(0.0, 4.0, 0.0), Vec3::NEG_Y, Vec3::Z),
            );
            let projection = p.input(
                "Projection",
                glam::camera::rh::proj::directx::perspective(std::f32::consts::FRAC_PI_4, 1.0, 0.05, 15.0),
            );
            let color = p.input("Color", Color::WHITE);
            let intensity = p.input("Intensity", 500.0f32);
            let texture = p.input("Texture ID", -1i64);
            let softness = p.input("Softness", 0.3f32);
            let shadow = p.input(SHADOW_SLICE, -1i64);
            move |cx| {
                require_finite(cx, view)?;
                require_finite(cx, projection)?;
                require_finite(cx, color)?;
                require_finite(cx, intensity)?;
                require_finite(cx, texture)?;
                require_finite(cx, softness)?;
                let shadows = cx.get(shadow)?.to_vec();
                let (views, projections, colors): (&[Mat4], &[Mat4], &[Color]) =
                    (cx.get(view)?, cx.get(projection)?, cx.get(color)?);
                let (intensities, textures, softness) =
                    (cx.get(intensity)?, cx.get(texture)?, cx.get(softness)?);
                let n = slice_count([
                    chain.id_count(cx)?,
                    views.len(),
                    projections.len(),
                    colors.len(),
                    intensities.len(),
                    textures.len(),
                    softness.len(),
                    shadows.len(),
                ]);
                let placement = cycled(views, n).zip(cycled(projections, n)).zip(cycled(colors, n));
                let look = cycled(intensities, n).zip(cycled(textures, n)).zip(cycled(softness, n));
                let lights: Vec<SpotLight> = placement
                    .zip(look)
                    .enumerate()
                    .map(|(i, (((view, projection), color), ((intensity, texture), softness)))| SpotLight {
                        shadow: shadow_slice(&shadows, i),
                        view: *view,
                        projection: *projection,
                        color: rgb(color),
                        intensity: *intensity,
                        texture: u32::try_from(*texture).ok(),
                        softness: *softness,
                    })
                    .collect();
                chain.add(cx, lights)
            }
        }),
    );
    let name = "AddLight (Sun)";
    r.add(
        NodeDef::new(
            name,
            super::CATEGORY,
            "Adds parallel lights, one per slice: the direction the light travels, linear colour \
             and illuminance in lux.",
        )
        .with_pins(|p| {
            let chain = Chain::<SunLight>::declare(p, name, ResourceKind::SunLights);
            let direction = p.input("Direction", Vec3::new(-0.3, -1.0, -0.2));
            let color = p.input("Color", Color::WHITE);
            let illuminance = p.input("Illuminance", 2.0f32);
            let shadow = p.input(SHADOW_SLICE, -1i64);
            move |cx| {
                require_finite(cx, direction)?;
                require_finite(cx, color)?;
                require_finite(cx, illuminance)?;
                let shadows = cx.get(shadow)?.to_vec();
                let (directions, colors, illuminances) =
                    (cx.get(direction)?, cx.get(color)?, cx.get(illuminance)?);
                let n = slice_count([
                    chain.id_count(cx)?,
                    directions.len(),
                    colors.len(),
                    illuminances.len(),
                    shadows.len(),
                ]);
                let lights: Vec<SunLight> = cycled(directions, n)
                    .zip(cycled(colors, n))
                    .zip(cycled(illuminances, n))
                    .enumerate()
                    .map(|(i, ((direction, color), illuminance))| SunLight {
                        shadow: shadow_slice(&shadows, i),
                        direction: *direction,
                        color: rgb(color),
                        illuminance: *illuminance,
                    })
                    .collect();
                chain.add(cx, lights)
            }
        }),
    );
}

/// The pin that says which slice of a `ShadowMap` node holds a light's shadow.
pub const SHADOW_SLICE: &str = "Shadow Slice";

/// Light `i`'s shadow slice from the Shadow Slice pin (cycled); negative: casts none.
fn shadow_slice(slices: &[i64], i: usize) -> Option<u32> {
    match slices.len() {
        0 => None,
        len => u32::try_from(slices[i % len]).ok(),
    }
}

fn rgb(c: &Color) -> Vec3 {
    Vec3::new(c.r, c.g, c.b)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn one_id_names_a_whole_spread_and_a_full_spread_is_taken_as_is() {
        assert_eq!(light_ids(&["spot".into()], 3), ["spot0", "spot1", "spot2"]);
        assert_eq!(light_ids(&["a".into(), "b".into()], 2), ["a", "b"]);
        assert_eq!(light_ids(&["a".into(), "b".into()], 3), ["a0", "b0", "a1"]);
        assert_eq!(light_ids(&[], 2), ["0", "1"]);
        assert_eq!(
            first_duplicate(&["a".into(), "b".into(), "a".into()]),
            Some("a")
        );
        assert_eq!(first_duplicate(&["a".into(), "b".into()]), None);
    }
}
