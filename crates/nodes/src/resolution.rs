//! The `Resolution` pin the screen-space effects share (SSAO, HBAO, SSGI,
//! SSR, DOF): a quality setting that runs the effect's expensive pass at
//! half resolution with a depth-aware upsample (render::resolution).
//! SSAO, HBAO, SAO, SSGI and SSR offer Auto (their default: Half from
//! 1920x1080 on, render::resolution::AUTO_HALF_FROM_PIXELS); DOF, whose
//! Half measured slower than its Full, offers Full and Half only.

use spreadlight_graph::{Choice, Choices, EnumDef, EvalContext, In, NodeDef, NodeError, Pins};
use spreadlight_render::resolution::Resolution;

pub static RESOLUTION: EnumDef = EnumDef {
    name: "Resolution",
    options: &Resolution::NAMES,
};

/// What the pin means, for the nodes' help.
pub const HELP: &str = " Resolution: Auto (the default: Half for frames of 1920x1080 pixels and more, Full below; \
     the environment variable SPREADLIGHT_RESOLUTION_AUTO=full|half|size forces it), Full (every pixel, the \
     reference) or Half (the expensive pass for one pixel in four and, for AO and SSGI, the temporal blend and the \
     blur at half size too, upsampled once with depth awareness so nothing bleeds across silhouettes; a fraction of \
     the cost, the error that `spreadlight accuracy` reports).";

/// DOF's line: no Auto.
pub const HELP_FULL_HALF: &str = " Resolution: Full (every pixel, the reference; the default) or Half (the blur for one \
     pixel in four, upsampled with depth awareness; the error that `spreadlight accuracy` reports).";

/// Add the pin (default Auto) and its line in the node's help.
pub fn pin(mut def: NodeDef) -> NodeDef {
    def.help = format!("{}{HELP}", def.help).into();
    def.input_enum("Resolution", &RESOLUTION, Resolution::Auto.name())
}

/// The pin's value at `index`.
pub fn read(cx: &EvalContext<'_>, index: usize) -> Result<Resolution, NodeError> {
    match cx.enum_slices(index)?.first() {
        None => Ok(Resolution::Auto),
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

/// DOF's options: Full and Half (its Half measured slower, so no Auto).
pub static FULL_HALF: Choices<Resolution> =
    Choices::new("DOF Resolution", &["Full", "Half"], &Resolution::RESOLVED);

/// The pin's line in the node's help, for a node that declares the pin with
/// [`input`].
pub fn with_help(mut def: NodeDef) -> NodeDef {
    def.help = format!("{}{HELP}", def.help).into();
    def
}

/// Declare the pin (default Auto: Full below 1920x1080, so small frames
/// render as before; a patch that says Full or Half keeps it).
pub fn input(p: &mut Pins<'_>) -> In<Choice<Resolution>> {
    p.input_choice("Resolution", &RESOLUTIONS, Resolution::Auto)
}

/// DOF's line in its help, for a node that declares [`input_full_half`].
pub fn with_full_half_help(mut def: NodeDef) -> NodeDef {
    def.help = format!("{}{HELP_FULL_HALF}", def.help).into();
    def
}

/// DOF's pin: Full or Half, default Full.
pub fn input_full_half(p: &mut Pins<'_>) -> In<Choice<Resolution>> {
    p.input_choice("Resolution", &FULL_HALF, Resolution::Full)
}

#[cfg(test)]
mod tests {
    use spreadlight_graph::{PinType, Spread};

    /// The pins' options and defaults: Auto first and the default on the
    /// effects that offer it (an old patch's Full or Half is still an
    /// option), Full and Half on DOF's, default Full.
    #[test]
    fn auto_is_the_default_of_every_resolution_pin_but_dofs() {
        let registry = crate::registry();
        for node in ["SSAO", "HBAO", "SSGI", "SSR", "DOF"] {
            let def = registry
                .get(node)
                .unwrap_or_else(|| panic!("{node} is registered"));
            let pin = def
                .inputs
                .iter()
                .find(|p| &*p.name == "Resolution")
                .unwrap_or_else(|| panic!("{node} has a Resolution pin"));
            let PinType::Enum(choices) = pin.ty else {
                panic!("{node}'s Resolution is a choice");
            };
            let (options, default): (&[&str], _) = if node == "DOF" {
                (&["Full", "Half"], "Full")
            } else {
                (&["Auto", "Full", "Half"], "Auto")
            };
            assert_eq!(choices.options, options, "{node}");
            assert_eq!(
                pin.default,
                Spread::Enum(vec![default.to_owned()]),
                "{node}"
            );
        }
    }
}
