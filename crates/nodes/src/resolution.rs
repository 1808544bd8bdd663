//! The `Resolution` pin the screen-space effects share (SSAO, HBAO, SSGI,
//! SSR, DOF): a quality setting that runs the effect's expensive pass at
//! half resolution with a depth-aware upsample (render::resolution).

use spreadlight_graph::{Choice, Choices, EnumDef, EvalContext, In, NodeDef, NodeError, Pins};
use spreadlight_render::resolution::Resolution;

pub static RESOLUTION: EnumDef = EnumDef {
    name: "Resolution",
    options: &Resolution::NAMES,
};

/// What the pin means, for the nodes' help.
pub const HELP: &str = " Resolution: Full (every pixel, the reference) or Half (the expensive pass for one pixel in \
     four, upsampled with depth awareness so nothing bleeds across silhouettes; about a quarter of its cost, the error \
     that `spreadlight accuracy` reports).";

/// Add the pin (default Full, so a patch without it renders as before) and
/// its line in the node's help.
pub fn pin(mut def: NodeDef) -> NodeDef {
    def.help = format!("{}{HELP}", def.help).into();
    def.input_enum("Resolution", &RESOLUTION, Resolution::Full.name())
}

/// The pin's value at `index`.
pub fn read(cx: &EvalContext<'_>, index: usize) -> Result<Resolution, NodeError> {
    match cx.enum_slices(index)?.first() {
        None => Ok(Resolution::Full),
        Some(name) => Resolution::parse(name).ok_or_else(|| {
            cx.input_error(
                index,
                format!("`{name}` is not one of {}", Resolution::NAMES.join(", ")),
            )
        }),
    }
}

/// The options as [`Resolution`] values, for typed pins.
pub static RESOLUTIONS: Choices<Resolution> =
    Choices::new("Resolution", &Resolution::NAMES, &Resolution::ALL);

/// The pin's line in the node's help, for a node that declares the pin with
/// [`input`].
pub fn with_help(mut def: NodeDef) -> NodeDef {
    def.help = format!("{}{HELP}", def.help).into();
    def
}

/// Declare the pin (default Full, so a patch without it renders as before).
pub fn input(p: &mut Pins<'_>) -> In<Choice<Resolution>> {
    p.input_choice("Resolution", &RESOLUTIONS, Resolution::Full)
}
