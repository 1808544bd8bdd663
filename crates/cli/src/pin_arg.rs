//! `ID.PIN=VALUE` command-line arguments that name one input of a patch's
//! node (`bench --set`, `bench --orbit`): split, the node found and the input
//! checked, with errors that name the flag and the whole argument.

use anyhow::Context;
use spreadlight_graph::{NodeId, Patch, PinType};

/// An argument whose node exists and whose pin is one of its inputs.
pub struct PinArg<'t> {
    pub node: NodeId,
    pub pin: &'t str,
    /// The text after `=`, unparsed: its meaning is the flag's.
    pub value: &'t str,
    pub ty: PinType,
}

impl<'t> PinArg<'t> {
    /// `text` of `--FLAG`, expected as `ID.PIN=FORM` (FORM names the value in errors).
    pub fn parse(patch: &Patch, flag: &str, form: &str, text: &'t str) -> anyhow::Result<Self> {
        let expected = || format!("`--{flag} {text}`: expected ID.PIN={form}");
        let (target, value) = text.rsplit_once('=').with_context(expected)?;
        let (id, pin) = target.split_once('.').with_context(expected)?;
        let id: u32 = id
            .trim()
            .trim_start_matches('#')
            .parse()
            .with_context(|| format!("`--{flag} {text}`: `{id}` is not a node id"))?;
        let node = patch
            .node(NodeId(id))
            .with_context(|| format!("`--{flag} {text}`: the patch has no node #{id}"))?;
        let registry = spreadlight_nodes::registry();
        let def = registry
            .get(&node.type_name)
            .with_context(|| format!("`--{flag} {text}`: node #{id} has an unknown type"))?;
        let k = def.input_index(pin).with_context(|| {
            format!(
                "`--{flag} {text}`: node #{id} `{}` has no input `{pin}`",
                def.name
            )
        })?;
        Ok(PinArg {
            node: NodeId(id),
            pin,
            value,
            ty: def.inputs[k].ty,
        })
    }
}
