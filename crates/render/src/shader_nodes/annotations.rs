//! The annotations of a shader node file: `// @...` comment lines that stay
//! valid WGSL, so editors and naga read the file as it is. What each says is
//! documented in docs/shader-nodes.md; this module only reads them, keeping
//! each one's line and column for error messages.

use std::collections::BTreeMap;

use super::error::{ShaderNodeError, Span};
use crate::frame_graph::{Lifetime, SizeRule};
use crate::light_kind::LightKind;

/// Where in the file: 1-based line and column.
pub type At = Span;

/// A render target the passes write: `// @target NAME LIFETIME FORMAT [scale=S|size=WxH] [clear=r,g,b,a]`.
#[derive(Clone, Debug, PartialEq)]
pub struct TargetDecl {
    pub name: String,
    pub lifetime: Lifetime,
    pub format: wgpu::TextureFormat,
    pub size: SizeRule,
    /// Filled before the target is written (a persistent one only when it is fresh).
    pub clear: Option<[f32; 4]>,
    pub at: At,
}

/// How often a pass runs.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Repeat {
    Once,
    /// A fixed number of times, each reading the last one's output.
    Times(u32),
    /// Each iteration at `step` times the last one's size (rounded up), until
    /// the destination is at most `width` x `height`.
    Until {
        width: u32,
        height: u32,
    },
}

/// `// @pass ENTRY -> TARGET[, TARGET] [repeat=N|repeat=until:WxH] [step=S] [skip=PIN]`.
#[derive(Clone, Debug, PartialEq)]
pub struct PassDecl {
    pub entry: String,
    pub targets: Vec<String>,
    pub repeat: Repeat,
    /// Scale per iteration of a repeated pass (1 when absent).
    pub step: f32,
    /// A Bool pin that, when on, skips the pass: its first texture read passes through.
    pub skip: Option<String>,
    pub at: At,
}

/// What a comment on a uniform field says: `// @pin "Name" default=.. min=.. max=.. color bool`.
/// The settings are checked against each other here (a range whose `min` is
/// above its `max`, a default outside the range, a range on a `bool` or
/// `color` pin are errors at the setting); against the field's type in
/// uniform_layout.rs.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PinDecl {
    pub display: Option<String>,
    pub default: Option<Vec<f32>>,
    pub min: Option<f32>,
    pub max: Option<f32>,
    pub color: bool,
    pub boolean: bool,
    pub at: At,
    /// Where the range is written (its first `min=` or `max=`), for errors about it.
    pub range_at: Option<At>,
    /// Alone on its line (so it may annotate the field on the next line).
    pub own_line: bool,
}

/// A `#ifdef` switch with a Bool pin: `// @switch NAME [default=true] ["Display"]`.
#[derive(Clone, Debug, PartialEq)]
pub struct SwitchDecl {
    pub define: String,
    pub display: String,
    pub default: bool,
    pub at: At,
}

/// A `#ifdef` choice with an Enum pin:
/// `// @enum NAME ["Display"] Option|Option|... [default=Option]`. The
/// selected option `#define`s `NAME_OPTION` (upper case), one permutation
/// per option used.
#[derive(Clone, Debug, PartialEq)]
pub struct EnumDecl {
    pub name: String,
    pub display: String,
    pub options: Vec<String>,
    /// Index of the default option.
    pub default: usize,
    pub at: At,
}

impl EnumDecl {
    /// What option `index` defines: `PATTERN_CHECKER` for option `Checker` of `PATTERN`.
    pub fn define(&self, index: usize) -> Option<String> {
        let option = self.options.get(index)?;
        Some(format!("{}_{}", self.name, option.to_uppercase()))
    }
}

/// How a declared sampler addresses past the edge (it always filters linearly).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct SamplerDecl {
    pub repeat: bool,
}

/// Everything the annotations of one file declare.
#[derive(Clone, Debug, Default)]
pub struct Annotations {
    pub category: Option<String>,
    pub help: Vec<String>,
    /// Texture variable -> pin name (`// @input VAR ["Pin Name"]`).
    pub inputs: Vec<(String, String, At)>,
    /// G-buffer bindings by name (`// @gbuffer depth normals camera`).
    pub gbuffer: Vec<(String, At)>,
    pub samplers: BTreeMap<String, SamplerDecl>,
    pub targets: Vec<TargetDecl>,
    pub passes: Vec<PassDecl>,
    pub switches: Vec<SwitchDecl>,
    /// Enum choices (`// @enum`), after the Bool switches among the pins.
    pub enums: Vec<EnumDecl>,
    /// Extra targets shown as output pins (`// @output TARGET`).
    pub outputs: Vec<(String, At)>,
    /// Per source line (1-based): the `@pin` annotation there, for the field on it or below it.
    pub pins: BTreeMap<u32, PinDecl>,
    /// `// @material`: the file is a DeferredBase material (its `surface` function), not an effect.
    pub material: Option<At>,
    /// `// @light point spot sun`: the file is a light shader (its `light`
    /// function) for these light types, not an effect.
    pub light: Option<(At, Vec<LightKind>)>,
}

/// The G-buffer names a shader may bind: its textures and its camera uniform.
pub const GBUFFER_NAMES: &[&str] = &["color", "normals", "depth", "velocity", "camera"];

impl Annotations {
    /// Read every `// @` line of `source` (`file` names it in errors).
    pub fn parse(file: &str, source: &str) -> Result<Self, ShaderNodeError> {
        let mut a = Annotations::default();
        for (index, line) in source.lines().enumerate() {
            let Some(start) = line.find("// @") else {
                continue;
            };
            let at = Span {
                line: index as u32 + 1,
                column: start as u32 + 4,
            };
            let text = &line[start + 4..];
            let (word, rest) = text.split_once(char::is_whitespace).unwrap_or((text, ""));
            let rest = rest.trim();
            // The 1-based column `rest` starts at, so a setting's error points at the setting.
            let rest_column = (line.trim_end().len() - rest.len()) as u32 + 1;
            let fail = |message: String| ShaderNodeError::at(file, at, message);
            match word {
                "category" => a.category = Some(rest.to_owned()),
                "help" => a.help.push(rest.to_owned()),
                "input" => {
                    let (var, display) = name_and_display(rest);
                    let var =
                        var.ok_or_else(|| fail("`@input` needs a texture variable".into()))?;
                    let pin = display.unwrap_or_else(|| title(&var));
                    a.inputs.push((var, pin, at));
                }
                "gbuffer" => {
                    for name in rest.split_whitespace() {
                        if !GBUFFER_NAMES.contains(&name) {
                            return Err(fail(format!(
                                "`{name}` is not a G-buffer name (known: {})",
                                GBUFFER_NAMES.join(", ")
                            )));
                        }
                        a.gbuffer.push((name.to_owned(), at));
                    }
                }
                "sampler" => {
                    let mut words = rest.split_whitespace();
                    let var = words
                        .next()
                        .ok_or_else(|| fail("`@sampler` needs a variable".into()))?;
                    let mut decl = SamplerDecl { repeat: false };
                    for w in words {
                        match w {
                            "clamp" => decl.repeat = false,
                            "repeat" => decl.repeat = true,
                            other => {
                                return Err(fail(format!(
                                    "unknown sampler setting `{other}` (clamp, repeat; samplers filter linearly)"
                                )));
                            }
                        }
                    }
                    a.samplers.insert(var.to_owned(), decl);
                }
                "target" => a.targets.push(parse_target(rest, at).map_err(fail)?),
                "pass" => a.passes.push(parse_pass(rest, at).map_err(fail)?),
                "switch" => {
                    let (define, display) = name_and_display(rest);
                    let define =
                        define.ok_or_else(|| fail("`@switch` needs a define name".into()))?;
                    let default = rest.split_whitespace().any(|w| w == "default=true");
                    a.switches.push(SwitchDecl {
                        display: display.unwrap_or_else(|| title(&define)),
                        define,
                        default,
                        at,
                    });
                }
                "output" => {
                    let target = rest
                        .split_whitespace()
                        .next()
                        .ok_or_else(|| fail("`@output` needs a target name".into()))?;
                    a.outputs.push((target.to_owned(), at));
                }
                "material" => a.material = Some(at),
                "light" => a.light = Some((at, parse_light_kinds(rest).map_err(fail)?)),
                "enum" => a.enums.push(parse_enum(rest, at).map_err(fail)?),
                "pin" => {
                    let mut decl = parse_pin(rest, at, rest_column)
                        .map_err(|(place, message)| ShaderNodeError::at(file, place, message))?;
                    decl.own_line = line[..start].trim().is_empty();
                    a.pins.insert(at.line, decl);
                }
                other => {
                    return Err(fail(format!(
                        "unknown annotation `@{other}` (category, help, input, gbuffer, sampler, target, \
                         pass, switch, enum, output, pin, material, light)"
                    )));
                }
            }
        }
        Ok(a)
    }

    pub fn target(&self, name: &str) -> Option<&TargetDecl> {
        self.targets.iter().find(|t| t.name == name)
    }
}

/// `point spot sun` (also `point|spot`, `point, sun`): the light types a
/// light shader declares, each once, in the order written.
fn parse_light_kinds(rest: &str) -> Result<Vec<LightKind>, String> {
    let mut kinds = Vec::new();
    for word in rest
        .split(|c: char| c.is_whitespace() || c == '|' || c == ',')
        .filter(|w| !w.is_empty())
    {
        let kind = match word {
            "point" => LightKind::Point,
            "spot" => LightKind::Spot,
            "sun" => LightKind::Sun,
            other => {
                return Err(format!("unknown light type `{other}` (point, spot, sun)"));
            }
        };
        if kinds.contains(&kind) {
            return Err(format!("light type `{word}` is declared twice"));
        }
        kinds.push(kind);
    }
    if kinds.is_empty() {
        return Err("`@light` needs the light types it shades: point, spot, sun".into());
    }
    Ok(kinds)
}

/// `Name "Display Name" ...` -> the first word and the quoted text, if any.
fn name_and_display(rest: &str) -> (Option<String>, Option<String>) {
    let name = rest
        .split_whitespace()
        .next()
        .filter(|w| !w.starts_with('"'))
        .map(str::to_owned);
    (name, quoted(rest))
}

fn quoted(text: &str) -> Option<String> {
    let start = text.find('"')?;
    let end = text[start + 1..].find('"')?;
    Some(text[start + 1..start + 1 + end].to_owned())
}

/// `blur_radius` -> `Blur Radius`: a field's default pin name.
pub fn title(name: &str) -> String {
    name.split('_')
        .filter(|w| !w.is_empty())
        .map(|w| {
            let mut c = w.chars();
            c.next()
                .map(|f| f.to_uppercase().chain(c).collect::<String>())
                .unwrap_or_default()
        })
        .collect::<Vec<_>>()
        .join(" ")
}

fn numbers(text: &str) -> Result<Vec<f32>, String> {
    text.split(',')
        .map(|n| {
            n.trim()
                .parse::<f32>()
                .ok()
                // `inf` and `NaN` parse, but no pin, range or clear value means them.
                .filter(|v| v.is_finite())
                .ok_or_else(|| format!("`{n}` is not a finite number"))
        })
        .collect()
}

fn size_pair(text: &str) -> Result<(u32, u32), String> {
    let (w, h) = text
        .split_once('x')
        .ok_or_else(|| format!("`{text}` is not a size like 64x64"))?;
    let parse = |s: &str| {
        s.trim()
            .parse::<u32>()
            .ok()
            .filter(|v| *v > 0)
            .ok_or_else(|| format!("`{text}` is not a size like 64x64"))
    };
    Ok((parse(w)?, parse(h)?))
}

/// The storage formats a target may have (those compute can write on every adapter).
pub fn format_by_name(name: &str) -> Option<wgpu::TextureFormat> {
    use wgpu::TextureFormat as F;
    Some(match name {
        "rgba8unorm" => F::Rgba8Unorm,
        "rgba16float" => F::Rgba16Float,
        "rgba32float" => F::Rgba32Float,
        "r32float" => F::R32Float,
        "rg32float" => F::Rg32Float,
        _ => return None,
    })
}

fn parse_target(rest: &str, at: At) -> Result<TargetDecl, String> {
    let words: Vec<&str> = rest.split_whitespace().collect();
    let [name, lifetime, format, settings @ ..] = words.as_slice() else {
        return Err("`@target` needs a name, a lifetime and a format".into());
    };
    let lifetime = match *lifetime {
        "temporary" => Lifetime::Temporary,
        "permanent" => Lifetime::Permanent,
        "persistent" => Lifetime::Persistent,
        other => {
            return Err(format!(
                "unknown lifetime `{other}` (temporary, permanent, persistent)"
            ));
        }
    };
    let format = format_by_name(format).ok_or_else(|| {
        format!("unknown target format `{format}` (rgba8unorm, rgba16float, rgba32float, r32float, rg32float)")
    })?;
    let mut target = TargetDecl {
        name: (*name).to_owned(),
        lifetime,
        format,
        size: SizeRule::Relative(1.0),
        clear: None,
        at,
    };
    for setting in settings {
        match setting.split_once('=') {
            Some(("scale", v)) => {
                let s: f32 = v.parse().map_err(|_| format!("`{v}` is not a scale"))?;
                if !(s.is_finite() && s > 0.0 && s <= 16.0) {
                    return Err(format!("scale {s} is outside 0..16"));
                }
                target.size = SizeRule::Relative(s);
            }
            Some(("size", v)) => {
                let (width, height) = size_pair(v)?;
                target.size = SizeRule::Absolute { width, height };
            }
            Some(("clear", v)) => {
                let c = match numbers(v)?.as_slice() {
                    [v] => [*v; 4],
                    [r, g, b, a] => [*r, *g, *b, *a],
                    _ => return Err(format!("clear `{v}` is one number or four")),
                };
                target.clear = Some(c);
            }
            _ => {
                return Err(format!(
                    "unknown target setting `{setting}` (scale=, size=, clear=)"
                ));
            }
        }
    }
    Ok(target)
}

fn parse_pass(rest: &str, at: At) -> Result<PassDecl, String> {
    let (entry, after) = rest
        .split_once("->")
        .ok_or_else(|| "`@pass` is `ENTRY -> TARGET`".to_owned())?;
    let entry = entry.trim();
    if entry.is_empty() {
        return Err("`@pass` needs an entry point".into());
    }
    let mut targets = Vec::new();
    let mut pass = PassDecl {
        entry: entry.to_owned(),
        targets: Vec::new(),
        repeat: Repeat::Once,
        step: 1.0,
        skip: None,
        at,
    };
    for word in after.split(|c: char| c.is_whitespace() || c == ',') {
        match word.split_once('=') {
            None if word.is_empty() => {}
            None => targets.push(word.to_owned()),
            Some(("repeat", v)) => {
                pass.repeat = match v.strip_prefix("until:") {
                    Some(size) => {
                        let (width, height) = size_pair(size)?;
                        Repeat::Until { width, height }
                    }
                    None => Repeat::Times(
                        v.parse()
                            .ok()
                            .filter(|n| (1..=64).contains(n))
                            .ok_or_else(|| format!("repeat `{v}` is not 1..64 or until:WxH"))?,
                    ),
                }
            }
            Some(("step", v)) => {
                pass.step = v
                    .parse()
                    .ok()
                    .filter(|s: &f32| s.is_finite() && *s > 0.0 && *s <= 1.0)
                    .ok_or_else(|| format!("step `{v}` is not in 0..1"))?;
            }
            Some(("skip", v)) => pass.skip = Some(v.to_owned()),
            Some(_) => {
                return Err(format!(
                    "unknown pass setting `{word}` (repeat=, step=, skip=)"
                ));
            }
        }
    }
    if targets.is_empty() {
        return Err(format!("pass `{entry}` names no destination target"));
    }
    if matches!(pass.repeat, Repeat::Until { .. }) && pass.step >= 1.0 {
        return Err("`repeat=until:` needs a `step=` below 1 so the target shrinks".into());
    }
    pass.targets = targets;
    Ok(pass)
}

fn parse_enum(rest: &str, at: At) -> Result<EnumDecl, String> {
    let (name, display) = name_and_display(rest);
    let name = name.ok_or("`@enum` needs a define name")?;
    // Settings are the words outside the quoted name, after the define name.
    let unquoted = match (rest.find('"'), rest.rfind('"')) {
        (Some(a), Some(b)) if b > a => format!("{} {}", &rest[..a], &rest[b + 1..]),
        _ => rest.to_owned(),
    };
    let mut options: Vec<String> = Vec::new();
    let mut default = None;
    for word in unquoted.split_whitespace().skip(1) {
        match word.split_once('=') {
            Some(("default", v)) => default = Some(v.to_owned()),
            Some(_) => return Err(format!("unknown enum setting `{word}` (default=)")),
            None => {
                for option in word.split('|').filter(|o| !o.is_empty()) {
                    if !option
                        .chars()
                        .all(|c| c.is_ascii_alphanumeric() || c == '_')
                    {
                        return Err(format!(
                            "enum option `{option}` is not a name (letters, digits, _): it becomes a define"
                        ));
                    }
                    if options.iter().any(|o| o.eq_ignore_ascii_case(option)) {
                        return Err(format!("enum option `{option}` is listed twice"));
                    }
                    options.push(option.to_owned());
                }
            }
        }
    }
    if options.len() < 2 {
        return Err("`@enum` lists two or more options: `@enum NAME A|B|C`".into());
    }
    let default = match default {
        Some(d) => options.iter().position(|o| *o == d).ok_or_else(|| {
            format!(
                "default `{d}` is not one of the options {}",
                options.join("|")
            )
        })?,
        None => 0,
    };
    Ok(EnumDecl {
        display: display.unwrap_or_else(|| title(&name.to_lowercase())),
        name,
        options,
        default,
        at,
    })
}

/// The words of `rest` outside double quotes, with their byte offsets.
fn settings(rest: &str) -> Vec<(usize, &str)> {
    let mut words = Vec::new();
    let mut start = None;
    let mut quoted = false;
    for (i, c) in rest.char_indices() {
        let ends = c == '"' || (!quoted && c.is_whitespace());
        if ends {
            if let Some(s) = start.take() {
                words.push((s, &rest[s..i]));
            }
            quoted ^= c == '"';
        } else if !quoted && start.is_none() {
            start = Some(i);
        }
    }
    if let Some(s) = start {
        words.push((s, &rest[s..]));
    }
    words
}

/// `// @pin` settings; an error comes with the place of the setting it is about.
/// `rest_column` is the 1-based column where `rest` starts on line `at.line`.
fn parse_pin(rest: &str, at: At, rest_column: u32) -> Result<PinDecl, (At, String)> {
    let mut pin = PinDecl {
        display: quoted(rest),
        at,
        ..Default::default()
    };
    let place = |offset: usize| Span {
        line: at.line,
        column: rest_column + offset as u32,
    };
    // A range bound is one number.
    let bound = |name: &str, v: &str| -> Result<f32, String> {
        match numbers(v)?.as_slice() {
            [x] => Ok(*x),
            _ => Err(format!("`{name}=` is one number, not `{v}`")),
        }
    };
    let mut default_at = at;
    let mut min_at = None;
    let mut max_at = None;
    for (offset, word) in settings(rest) {
        let here = place(offset);
        let parsed = match word.split_once('=') {
            Some(("default", v)) => {
                default_at = here;
                numbers(v).map(|n| pin.default = Some(n))
            }
            Some(("min", v)) => {
                min_at = Some(here);
                bound("min", v).map(|n| pin.min = Some(n))
            }
            Some(("max", v)) => {
                max_at = Some(here);
                bound("max", v).map(|n| pin.max = Some(n))
            }
            None if word == "color" => {
                pin.color = true;
                Ok(())
            }
            None if word == "bool" => {
                pin.boolean = true;
                Ok(())
            }
            _ => Err(format!(
                "unknown pin setting `{word}` (\"Name\", default=, min=, max=, color, bool)"
            )),
        };
        parsed.map_err(|m| (here, m))?;
    }
    pin.range_at = min_at.or(max_at);
    if let Some(range_at) = pin.range_at {
        // Values outside a range are held to it when the node writes them, so
        // a range that cannot hold them, or a pin that is no range, would show
        // one value in the editor and render another.
        let what = if pin.boolean {
            Some("a `bool` pin is off or on")
        } else if pin.color {
            Some("a `color` pin is a colour, not a range")
        } else {
            None
        };
        if let Some(what) = what {
            return Err((range_at, format!("{what}: it takes no `min=` or `max=`")));
        }
    }
    if let (Some(min), Some(max)) = (pin.min, pin.max)
        && min > max
    {
        return Err((
            min_at.unwrap_or(at),
            format!("`min={min}` is above `max={max}`"),
        ));
    }
    if let Some(default) = &pin.default
        && let Some(v) = default
            .iter()
            .find(|v| pin.min.is_some_and(|m| **v < m) || pin.max.is_some_and(|m| **v > m))
    {
        return Err((
            default_at,
            format!(
                "default {v} is outside the pin's range {}",
                range_text(&pin)
            ),
        ));
    }
    Ok(pin)
}

/// `min..max` as written (an open end left empty).
pub fn range_text(pin: &PinDecl) -> String {
    let end = |v: Option<f32>| v.map_or(String::new(), |v| v.to_string());
    format!("{}..{}", end(pin.min), end(pin.max))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn targets_passes_and_pins_are_read_with_their_places() {
        let src = "// @category Filter\n\
                   // @target half temporary rgba16float scale=0.5\n\
                   // @target lum persistent r32float size=1x1 clear=0.5\n\
                   // @pass reduce -> half repeat=until:1x1 step=0.5 skip=Bypass\n\
                   struct P {\n    radius: f32, // @pin \"Blur Radius\" default=2 min=0 max=16\n}\n";
        let a = Annotations::parse("t.wgsl", src).expect("parses");
        assert_eq!(a.category.as_deref(), Some("Filter"));
        assert_eq!(a.targets[0].size, SizeRule::Relative(0.5));
        assert_eq!(a.targets[1].clear, Some([0.5, 0.5, 0.5, 0.5]));
        assert_eq!(
            a.passes[0].repeat,
            Repeat::Until {
                width: 1,
                height: 1
            }
        );
        assert_eq!(a.passes[0].skip.as_deref(), Some("Bypass"));
        let pin = &a.pins[&6];
        assert_eq!(pin.display.as_deref(), Some("Blur Radius"));
        assert_eq!((pin.min, pin.max), (Some(0.0), Some(16.0)));
    }

    #[test]
    fn an_enum_lists_its_options_and_defines_one_per_option() {
        let a = Annotations::parse(
            "e.wgsl",
            "// @enum PATTERN \"Pattern\" Marble|Checker|Wood default=Checker\n",
        )
        .expect("parses");
        let e = &a.enums[0];
        assert_eq!((e.display.as_str(), e.default), ("Pattern", 1));
        assert_eq!(e.options, ["Marble", "Checker", "Wood"]);
        assert_eq!(e.define(2).as_deref(), Some("PATTERN_WOOD"));
        let err = Annotations::parse("e.wgsl", "\n// @enum MODE A|B default=C\n")
            .expect_err("bad default");
        assert!(
            err.to_string().starts_with("e.wgsl:2:4: default `C`"),
            "{err}"
        );
    }

    /// A pin whose settings contradict each other is refused at the setting:
    /// its value would be held to a range the editor does not show.
    #[test]
    fn a_pin_range_that_makes_no_sense_is_an_error_at_its_setting() {
        let cases = [
            (
                "  x: f32, // @pin min=4 max=1\n",
                "p.wgsl:1:19: `min=4` is above `max=1`",
            ),
            (
                "  x: f32, // @pin \"X\" default=9 min=0 max=4\n",
                "p.wgsl:1:23: default 9 is outside the pin's range 0..4",
            ),
            (
                "  // @pin default=0.5,-1 min=0\n  v: vec2<f32>,\n",
                "p.wgsl:1:11: default -1 is outside the pin's range 0..",
            ),
            (
                "  on: u32, // @pin bool default=1 max=1\n",
                "p.wgsl:1:35: a `bool` pin is off or on: it takes no `min=` or `max=`",
            ),
            (
                "  c: vec4<f32>, // @pin color min=0\n",
                "p.wgsl:1:31: a `color` pin is a colour, not a range",
            ),
            (
                "  x: f32, // @pin min=0,1\n",
                "p.wgsl:1:19: `min=` is one number",
            ),
            (
                "  x: f32, // @pin max=inf\n",
                "p.wgsl:1:19: `inf` is not a finite number",
            ),
        ];
        for (src, expected) in cases {
            let err = Annotations::parse("p.wgsl", src).expect_err(src);
            assert!(err.to_string().starts_with(expected), "{src}: {err}");
        }
        // Ranges that hold their defaults, open ends and equal ends are fine.
        for src in [
            "x: f32, // @pin default=2 min=0 max=4\n",
            "x: f32, // @pin default=-3 max=0\n",
            "x: f32, // @pin default=1 min=1 max=1\n",
        ] {
            Annotations::parse("p.wgsl", src).unwrap_or_else(|e| panic!("{src}: {e}"));
        }
    }

    #[test]
    fn a_bad_annotation_names_its_line_and_column() {
        let err = Annotations::parse("f.wgsl", "\n  // @target t forever rgba8unorm\n")
            .expect_err("bad lifetime");
        assert!(
            err.to_string().starts_with("f.wgsl:2:6: unknown lifetime"),
            "{err}"
        );
    }
}
