//! Pin types and the small value types that travel in spreads.
//!
//! A pin's type decides which spread variant it carries and which links are
//! legal. Resource types (meshes, textures, ...) are opaque here: the graph
//! crate knows nothing of the GPU, it only moves handles that later crates fill.

use std::any::Any as AnyValue;
use std::fmt;
use std::sync::Arc;

use serde::{Deserialize, Serialize};

/// A colour in linear RGBA (not sRGB): what shading maths wants.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Color {
    pub r: f32,
    pub g: f32,
    pub b: f32,
    pub a: f32,
}

/// White, as vvvv's colour IOBox starts.
impl Default for Color {
    fn default() -> Self {
        Color::WHITE
    }
}

impl Color {
    pub const WHITE: Color = Color::rgba(1.0, 1.0, 1.0, 1.0);
    pub const BLACK: Color = Color::rgba(0.0, 0.0, 0.0, 1.0);

    pub const fn rgba(r: f32, g: f32, b: f32, a: f32) -> Self {
        Color { r, g, b, a }
    }

    pub fn to_vec4(self) -> glam::Vec4 {
        glam::Vec4::new(self.r, self.g, self.b, self.a)
    }

    pub fn from_vec4(v: glam::Vec4) -> Self {
        Color::rgba(v.x, v.y, v.z, v.w)
    }
}

/// The closed set of choices of an enum pin, e.g. the mapping mode of `Map (Value)`.
///
/// Defined as a `static` next to the node that uses it; two enum pins link only
/// when they share the same definition (compared by name).
#[derive(Debug)]
pub struct EnumDef {
    pub name: &'static str,
    pub options: &'static [&'static str],
}

impl EnumDef {
    pub fn index_of(&self, option: &str) -> Option<usize> {
        self.options.iter().position(|o| *o == option)
    }
}

/// Kinds of opaque GPU-side resources. Later crates put the real objects behind
/// [`Resource`]; the runtime only needs to know which kinds may be linked.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum ResourceKind {
    Mesh,
    Buffer,
    Texture,
    GBuffer,
    MaterialWorld,
    /// A CPU-side material (features and parameters) before a `MaterialBuffer` uploads it into a `MaterialWorld`.
    Material,
    LightWorld,
    /// CPU-side lights of one type with their IDs (from `AddLight` nodes), before a light buffer uploads them.
    PointLights,
    SpotLights,
    SunLights,
    /// Shadow maps of one light type (from a `ShadowMap` node), for `CookTorrance`.
    Shadows,
    /// What a `DeferredBase` draws: instanced meshes with feature switches.
    Layer,
    /// A prefiltered environment for image-based light (from an `Environment` node).
    Environment,
    /// Sound up to the current frame (from `AudioFile` or `AudioIn`), for the analysis nodes.
    Audio,
}

/// A shared, opaque resource handle. Equality is identity: two handles are the
/// same slice when they point at the same object.
#[derive(Clone)]
pub struct Resource(pub Arc<dyn AnyValue + Send + Sync>);

impl Resource {
    pub fn new<T: AnyValue + Send + Sync>(value: T) -> Self {
        Resource(Arc::new(value))
    }

    pub fn downcast<T: AnyValue + Send + Sync>(&self) -> Option<&T> {
        self.0.downcast_ref::<T>()
    }

    /// Wrap an already shared value without a second allocation.
    pub fn from_arc<T: AnyValue + Send + Sync>(value: Arc<T>) -> Self {
        Resource(value)
    }

    /// The shared value itself, when it is a `T`.
    pub fn downcast_arc<T: AnyValue + Send + Sync>(&self) -> Option<Arc<T>> {
        self.0.clone().downcast::<T>().ok()
    }
}

impl PartialEq for Resource {
    fn eq(&self, other: &Self) -> bool {
        Arc::ptr_eq(&self.0, &other.0)
    }
}

impl fmt::Debug for Resource {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "Resource({:p})", Arc::as_ptr(&self.0))
    }
}

/// The type of a pin: which spread variant it carries.
#[derive(Clone, Copy, Debug)]
pub enum PinType {
    Float,
    Int,
    Bool,
    String,
    Vec2,
    Vec3,
    Vec4,
    Color,
    /// A 4x4 transform (vvvv's "Transform").
    Mat4,
    Enum(&'static EnumDef),
    Resource(ResourceKind),
    /// Accepts a spread of any type: for generic sinks such as `Probe`. Never an output type.
    Any,
}

impl PartialEq for PinType {
    fn eq(&self, other: &Self) -> bool {
        use PinType::*;
        match (self, other) {
            (Enum(a), Enum(b)) => a.name == b.name,
            (Resource(a), Resource(b)) => a == b,
            _ => std::mem::discriminant(self) == std::mem::discriminant(other),
        }
    }
}

impl PinType {
    /// Whether an output of type `self` may feed an input of type `to`.
    ///
    /// Besides equal types, the runtime converts the few pairs where no
    /// information an artist cares about is lost or invented: Int to Float,
    /// and Color to and from Vec4.
    pub fn links_to(self, to: PinType) -> bool {
        use PinType::*;
        self == to
            || matches!(
                (self, to),
                (_, Any) | (Int, Float) | (Color, Vec4) | (Vec4, Color)
            )
    }

    pub fn name(self) -> String {
        match self {
            PinType::Enum(def) => format!("Enum<{}>", def.name),
            PinType::Resource(kind) => format!("{kind:?}"),
            other => format!("{other:?}"),
        }
    }
}

impl fmt::Display for PinType {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.name())
    }
}
