//! A shadow filter as a shader key: which filter a forward light pass
//! compiles in (lit transparency's light passes, EnvironmentProbe's faces),
//! without the filter's settings, which are uniforms.

use super::filter::ShadowFilter;

/// The shadow filter compiled in (ShadowFilter without its settings).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum ShadowKey {
    None,
    Raw,
    Pcf,
    Pcss,
    Vsm,
}

impl ShadowKey {
    pub fn of(filter: Option<ShadowFilter>) -> Self {
        match filter {
            None => ShadowKey::None,
            Some(ShadowFilter::Raw) => ShadowKey::Raw,
            Some(ShadowFilter::Pcf { .. }) => ShadowKey::Pcf,
            Some(ShadowFilter::Pcss { .. }) => ShadowKey::Pcss,
            Some(ShadowFilter::Vsm { .. }) => ShadowKey::Vsm,
        }
    }

    pub(crate) fn features(self) -> impl Iterator<Item = &'static str> {
        let (on, filter) = match self {
            ShadowKey::None => (false, None),
            ShadowKey::Raw => (true, None),
            ShadowKey::Pcf => (true, Some("SHADOW_PCF")),
            ShadowKey::Pcss => (true, Some("SHADOW_PCSS")),
            ShadowKey::Vsm => (true, Some("SHADOW_VSM")),
        };
        on.then_some("SHADOWS").into_iter().chain(filter)
    }

    pub(crate) const ALL: [ShadowKey; 5] = [
        ShadowKey::None,
        ShadowKey::Raw,
        ShadowKey::Pcf,
        ShadowKey::Pcss,
        ShadowKey::Vsm,
    ];
}
