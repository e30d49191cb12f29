//! Scene parameters declared once. Each scene's parameters are one
//! [`params!`](crate::params!) struct: one row per parameter gives its field, type, default, value name, unit, range
//! check, help heading and help text, and from that row come the struct and its
//! `Default`, the scene-file key (the field's name, in the row's table), the
//! command-line option (the key with `-` for `_`) and its help, the range check, and
//! the value printed back by `--print-scene`. Nothing here knows the command line's
//! parser: the binary builds its options from [`ParamSet::params`].
//!
//! A value is read from a command-line word ([`Given::Text`]) or a scene-file value
//! ([`Given::Toml`]); every float must be finite, every value in its range, and an
//! error names the parameter by its key (`sun_elevation`), which the command line
//! shows as its option (`--sun-elevation`).

use std::fmt::Display;
use std::path::Path;

use crate::error::{Error, Result};

/// One parameter as scene files, the command line and `--help` know it.
#[derive(Clone, Debug, PartialEq)]
pub struct Param {
    /// The scene-file key and the struct's field ("sun_elevation").
    pub key: &'static str,
    /// The scene-file table it lives in ("" for the top level, "growth", "camera").
    pub table: &'static str,
    /// The `--help` heading it is listed under ("Simulation", "Camera").
    pub heading: &'static str,
    /// The value's name in `--help` ("DEG", "on|off"); empty for a key only scene
    /// files take (a table of rows, a list of points), which has no option.
    pub value_name: &'static str,
    /// The unit of the value ("degrees", "m", "" for a count or a name).
    pub unit: &'static str,
    /// What the parameter is, from the row's doc comment.
    pub help: String,
    /// The values it takes ("-2..=90", "> 0", "16..=1024, a power of two").
    pub range: String,
}

impl Param {
    /// The command-line option without its dashes: the key with `-` for `_`.
    pub fn flag(&self) -> String {
        self.key.replace('_', "-")
    }

    /// Whether the command line takes it (scene files take every parameter).
    pub fn on_command_line(&self) -> bool {
        !self.value_name.is_empty()
    }
}

/// A value as it comes in: a command-line word, or a scene file's value.
#[derive(Clone, Copy, Debug)]
pub enum Given<'a> {
    /// The text after `--option`.
    Text(&'a str),
    /// A value of a scene file.
    Toml(&'a toml::Value),
}

/// A type a parameter can have: read from a command-line word or a scene-file value,
/// written back to a scene file.
pub trait ParamValue: Sized {
    /// From a command-line word.
    fn from_text(text: &str) -> Result<Self, String>;
    /// From a scene file's value (default: a string, integer or float read as text).
    fn from_toml(value: &toml::Value) -> Result<Self, String> {
        match value {
            toml::Value::String(s) => Self::from_text(s),
            toml::Value::Integer(i) => Self::from_text(&i.to_string()),
            toml::Value::Float(x) => Self::from_text(&x.to_string()),
            toml::Value::Boolean(b) => Self::from_text(if *b { "true" } else { "false" }),
            other => Err(format!(
                "expected a name or a number, not {}",
                other.type_str()
            )),
        }
    }
    /// The value for a scene file; `None` for an unset optional value (left out).
    fn to_toml(&self) -> Option<toml::Value>;
    /// Reads either.
    fn from_given(given: Given<'_>) -> Result<Self, String> {
        match given {
            Given::Text(t) => Self::from_text(t),
            Given::Toml(v) => Self::from_toml(v),
        }
    }
}

/// Text as a scene-file value: an integer or a float when it reads as one, else a
/// string (so `pil = 2` and `mineral = "iron"` read back as written).
pub fn text_to_toml(text: &str) -> toml::Value {
    if let Ok(i) = text.parse::<i64>() {
        toml::Value::Integer(i)
    } else if let Ok(x) = text.parse::<f64>().map_err(drop).and_then(|x| {
        // Only plain numbers: "inf" and "nan" stay names.
        if x.is_finite() { Ok(x) } else { Err(()) }
    }) {
        toml::Value::Float(x)
    } else {
        toml::Value::String(text.to_owned())
    }
}

/// The message of a parse error, without the option name a type's own error adds.
fn message_of(e: impl Display) -> String {
    e.to_string()
}

/// Implements [`ParamValue`] through `FromStr` and `Display`: each such type has one
/// spelling on the command line and in scene files.
#[macro_export]
macro_rules! text_param {
    ($($ty:ty),+ $(,)?) => {$(
        impl $crate::params::ParamValue for $ty {
            fn from_text(text: &str) -> std::result::Result<Self, String> {
                text.trim()
                    .parse::<$ty>()
                    .map_err(|e| $crate::params::reason_for(text.trim(), e))
            }
            fn to_toml(&self) -> Option<toml::Value> {
                Some($crate::params::text_to_toml(&self.to_string()))
            }
        }
    )+};
}

/// What a parse error says, without the option name a type's own `Error` carries (the
/// caller names the parameter).
pub fn reason<E: Display + 'static>(e: E) -> String {
    let any: &dyn std::any::Any = &e;
    match any.downcast_ref::<Error>() {
        Some(Error::InvalidArgument { message, .. }) => message.clone(),
        _ => message_of(e),
    }
}

/// [`reason`], quoting the value (cut when long) where the reason does not
/// ("\"12x\": invalid digit found in string").
pub fn reason_for<E: Display + 'static>(text: &str, e: E) -> String {
    let reason = reason(e);
    let shown = crate::error::echo(text);
    if reason.contains(&shown) {
        reason
    } else {
        format!("\"{shown}\": {reason}")
    }
}

text_param!(u8, u32, u64, usize, String);

macro_rules! float_param {
    ($($ty:ty),+) => {$(
        impl ParamValue for $ty {
            fn from_text(text: &str) -> Result<Self, String> {
                let x: $ty = text
                    .trim()
                    .parse()
                    .map_err(|_| format!("\"{}\" is not a number", crate::error::echo(text)))?;
                if x.is_finite() {
                    Ok(x)
                } else {
                    Err(format!("{text} is not a finite number"))
                }
            }
            /// As the decimal the value prints as: an f32's 0.35, not the
            /// 0.3499999940395355 its widening to f64 gives.
            fn to_toml(&self) -> Option<toml::Value> {
                Some(toml::Value::Float(
                    self.to_string().parse().unwrap_or(f64::from(*self)),
                ))
            }
        }
    )+};
}
float_param!(f32, f64);

impl ParamValue for bool {
    /// `on`/`off` as the command line writes them, `true`/`false` too.
    fn from_text(text: &str) -> Result<Self, String> {
        match text.trim().to_ascii_lowercase().as_str() {
            "on" | "true" => Ok(true),
            "off" | "false" => Ok(false),
            other => Err(format!(
                "\"{}\" is not on or off",
                crate::error::echo(other)
            )),
        }
    }
    fn from_toml(value: &toml::Value) -> Result<Self, String> {
        match value {
            toml::Value::Boolean(b) => Ok(*b),
            toml::Value::String(s) => Self::from_text(s),
            other => Err(format!("expected true or false, not {}", other.type_str())),
        }
    }
    fn to_toml(&self) -> Option<toml::Value> {
        Some(toml::Value::Boolean(*self))
    }
}

impl<T: ParamValue> ParamValue for Option<T> {
    /// `none` (or `off`) for no value.
    fn from_text(text: &str) -> Result<Self, String> {
        match text.trim() {
            "none" => Ok(None),
            t => T::from_text(t).map(Some),
        }
    }
    fn from_toml(value: &toml::Value) -> Result<Self, String> {
        match value {
            toml::Value::String(s) if s == "none" => Ok(None),
            v => T::from_toml(v).map(Some),
        }
    }
    fn to_toml(&self) -> Option<toml::Value> {
        self.as_ref().and_then(T::to_toml)
    }
}

impl ParamValue for std::path::PathBuf {
    /// A file's path, as given.
    fn from_text(text: &str) -> Result<Self, String> {
        if text.trim().is_empty() {
            return Err("an empty path".to_owned());
        }
        Ok(Self::from(text))
    }
    fn to_toml(&self) -> Option<toml::Value> {
        Some(toml::Value::String(self.display().to_string()))
    }
}

/// Implements [`ParamValue`] through serde for values only scene files hold (tables
/// of rows, lists of points): the command line does not take them.
#[macro_export]
macro_rules! serde_param {
    ($($ty:ty),+ $(,)?) => {$(
        impl $crate::params::ParamValue for $ty {
            fn from_text(_text: &str) -> std::result::Result<Self, String> {
                Err("only scene files give this".to_owned())
            }
            fn from_toml(value: &toml::Value) -> std::result::Result<Self, String> {
                serde::Deserialize::deserialize(value.clone()).map_err(|e| e.to_string())
            }
            fn to_toml(&self) -> Option<toml::Value> {
                toml::Value::try_from(self).ok()
            }
        }
    )+};
}

/// A point x,y,z (`--eye`, `--target`; `[x, y, z]` in scene files).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Point3(pub [f32; 3]);

impl ParamValue for Point3 {
    fn from_text(text: &str) -> Result<Self, String> {
        let parts: Option<Vec<f32>> = text
            .split(',')
            .map(|p| p.trim().parse::<f32>().ok().filter(|c| c.is_finite()))
            .collect();
        match parts.as_deref() {
            Some(&[x, y, z]) => Ok(Point3([x, y, z])),
            _ => Err(format!(
                "\"{}\" is not three finite numbers x,y,z",
                crate::error::echo(text)
            )),
        }
    }
    fn from_toml(value: &toml::Value) -> Result<Self, String> {
        let items = value
            .as_array()
            .ok_or_else(|| format!("expected [x, y, z], not {}", value.type_str()))?;
        let numbers: Option<Vec<f32>> = items
            .iter()
            .map(|v| {
                v.as_float()
                    .or_else(|| v.as_integer().map(|i| i as f64))
                    .map(|x| x as f32)
                    .filter(|x| x.is_finite())
            })
            .collect();
        match numbers.as_deref() {
            Some(&[x, y, z]) => Ok(Point3([x, y, z])),
            _ => Err("expected [x, y, z] of three finite numbers".to_owned()),
        }
    }
    fn to_toml(&self) -> Option<toml::Value> {
        self.0
            .iter()
            .map(|c| c.to_toml())
            .collect::<Option<Vec<_>>>()
            .map(toml::Value::Array)
    }
}

/// The values a parameter takes: their description for `--help` and the test.
pub struct Check<T> {
    /// "0..=4", "> 0", "finite".
    pub text: String,
    test: Box<dyn Fn(&T) -> bool>,
}

impl<T> Check<T> {
    /// A check of `test`, described by `text`.
    pub fn new(text: impl Into<String>, test: impl Fn(&T) -> bool + 'static) -> Self {
        Self {
            text: text.into(),
            test: Box::new(test),
        }
    }

    /// Whether `value` passes.
    pub fn holds(&self, value: &T) -> bool {
        (self.test)(value)
    }
}

/// The message for a value a check refused: "must be in 1..=8", "must be > 0", "must be
/// one of 4, 8".
pub fn must_be(text: &str) -> String {
    if text.starts_with(['>', '<']) || text.starts_with("one of") {
        format!("must be {text}")
    } else {
        format!("must be in {text}")
    }
}

/// The range checks rows use.
pub mod check {
    use super::Check;
    use std::fmt::Display;
    use std::ops::RangeInclusive;

    /// Any value of the type (floats are finite already).
    pub fn any<T>() -> Check<T> {
        Check::new("", |_| true)
    }

    /// A bound as the help and messages show it: a float's many decimals as an
    /// exponent (`1e-9`, not `0.000000001`).
    fn bound<T: Display>(v: T) -> String {
        let text = v.to_string();
        match text.parse::<f64>() {
            Ok(f) if text.contains('.') && text.len() > 8 => format!("{f:e}"),
            _ => text,
        }
    }

    /// `lo..=hi`.
    pub fn within<T: PartialOrd + Display + Copy + 'static>(r: RangeInclusive<T>) -> Check<T> {
        let (lo, hi) = (*r.start(), *r.end());
        Check::new(format!("{}..={}", bound(lo), bound(hi)), move |v: &T| {
            lo <= *v && *v <= hi
        })
    }

    /// `(lo, hi]`: above `lo`, at most `hi`.
    pub fn above_to<T: PartialOrd + Display + Copy + 'static>(lo: T, hi: T) -> Check<T> {
        Check::new(format!("({lo}, {hi}]"), move |v: &T| lo < *v && *v <= hi)
    }

    /// `> lo`.
    pub fn above<T: PartialOrd + Display + Copy + 'static>(lo: T) -> Check<T> {
        Check::new(format!("> {lo}"), move |v: &T| *v > lo)
    }

    /// `>= lo`.
    pub fn at_least<T: PartialOrd + Display + Copy + 'static>(lo: T) -> Check<T> {
        Check::new(format!(">= {lo}"), move |v: &T| *v >= lo)
    }

    /// A power of two within `lo..=hi`.
    pub fn power_of_two(r: RangeInclusive<usize>) -> Check<usize> {
        let (lo, hi) = (*r.start(), *r.end());
        Check::new(format!("{lo}..={hi}, a power of two"), move |v: &usize| {
            v.is_power_of_two() && lo <= *v && *v <= hi
        })
    }

    /// One of the listed values.
    pub fn one_of<T: PartialEq + Display + Copy + 'static>(values: &'static [T]) -> Check<T> {
        let text = values
            .iter()
            .map(|v| v.to_string())
            .collect::<Vec<_>>()
            .join(", ");
        Check::new(format!("one of {text}"), move |v: &T| values.contains(v))
    }

    /// An optional value checked when given.
    pub fn optional<T: 'static>(inner: Check<T>) -> Check<Option<T>> {
        let text = inner.text.clone();
        Check::new(text, move |v: &Option<T>| {
            v.as_ref().is_none_or(|x| inner.holds(x))
        })
    }
}

/// A scene's parameters: the struct a [`params!`](crate::params!) block declares.
pub trait ParamSet: Clone + Default + PartialEq + Send + Sync + 'static {
    /// Every parameter, in declaration order.
    fn params() -> &'static [Param];
    /// The value of `key` for a scene file; `None` when unset or no such key.
    fn get(&self, key: &str) -> Option<toml::Value>;
    /// Sets `key`; the error says what is wrong with the value (not where it came
    /// from: the caller names the option or the file and line).
    fn set(&mut self, key: &str, given: Given<'_>) -> Result<(), String>;
    /// Every row's range check, in order; the error names the first parameter out of
    /// range by its key.
    fn check_rows(&self) -> Result<()>;
    /// The rows' checks and the scene's own checks across parameters.
    fn validate(&self) -> Result<()>;
}

/// Declares a scene's parameters (see the module documentation). Each row:
///
/// ```text
/// /// Help text: what it is.
/// [table, "Heading"] field: Type = default, "VALUE_NAME", "unit", check;
/// ```
///
/// `table` is `top` for the top level or the name of a scene-file table; an empty
/// value name makes a key only scene files take. After the rows, `validate = path;`
/// names a function `fn(&Self) -> Result<()>` with the checks across parameters.
#[macro_export]
macro_rules! params {
    (
        $(#[$meta:meta])*
        pub struct $name:ident {
            $(
                $(#[doc = $doc:literal])*
                [$table:ident, $heading:literal]
                $field:ident : $ty:ty = $default:expr, $value_name:literal, $unit:literal, $check:expr;
            )*
        }
        validate = $validate:path;
    ) => {
        $(#[$meta])*
        #[derive(Clone, Debug, PartialEq)]
        pub struct $name {
            $(
                $(#[doc = $doc])*
                pub $field: $ty,
            )*
        }

        impl Default for $name {
            fn default() -> Self {
                Self { $($field: $default,)* }
            }
        }

        impl $crate::params::ParamSet for $name {
            fn params() -> &'static [$crate::params::Param] {
                static PARAMS: std::sync::OnceLock<Vec<$crate::params::Param>> =
                    std::sync::OnceLock::new();
                PARAMS.get_or_init(|| {
                    vec![$(
                        $crate::params::Param {
                            key: stringify!($field),
                            table: $crate::params::table_name(stringify!($table)),
                            heading: $heading,
                            value_name: $value_name,
                            unit: $unit,
                            help: $crate::params::one_line(&[$($doc),*]),
                            range: {
                                let check: $crate::params::Check<$ty> = $check;
                                check.text
                            },
                        },
                    )*]
                })
            }

            fn get(&self, key: &str) -> Option<toml::Value> {
                match key {
                    $(stringify!($field) => $crate::params::ParamValue::to_toml(&self.$field),)*
                    _ => None,
                }
            }

            fn set(
                &mut self,
                key: &str,
                given: $crate::params::Given<'_>,
            ) -> std::result::Result<(), String> {
                match key {
                    $(stringify!($field) => {
                        self.$field = <$ty as $crate::params::ParamValue>::from_given(given)?;
                        Ok(())
                    })*
                    _ => Err(format!("no parameter {key}")),
                }
            }

            fn check_rows(&self) -> $crate::Result<()> {
                $({
                    let check: $crate::params::Check<$ty> = $check;
                    if !check.holds(&self.$field) {
                        return Err($crate::Error::invalid(
                            stringify!($field),
                            $crate::params::must_be(&check.text),
                        ));
                    }
                })*
                Ok(())
            }

            fn validate(&self) -> $crate::Result<()> {
                $crate::params::ParamSet::check_rows(self)?;
                $validate(self)
            }
        }
    };
}

/// `top` is the top level of a scene file ("").
pub fn table_name(table: &'static str) -> &'static str {
    if table == "top" { "" } else { table }
}

/// Doc-comment lines as one line of help.
pub fn one_line(lines: &[&str]) -> String {
    lines
        .iter()
        .flat_map(|l| l.split_whitespace())
        .collect::<Vec<_>>()
        .join(" ")
}

/// No checks across parameters.
pub fn no_more_checks<P>(_: &P) -> Result<()> {
    Ok(())
}

/// The value `P`'s default gives `key`, as `--help` shows it ("none" when unset).
pub fn default_text<P: ParamSet>(key: &str) -> String {
    P::default()
        .get(key)
        .map_or_else(|| "none".to_owned(), |v| value_text(&v))
}

/// A scene-file value as the command line would write it.
pub fn value_text(value: &toml::Value) -> String {
    match value {
        toml::Value::String(s) => s.clone(),
        toml::Value::Boolean(true) => "on".to_owned(),
        toml::Value::Boolean(false) => "off".to_owned(),
        toml::Value::Array(items) => items.iter().map(value_text).collect::<Vec<_>>().join(","),
        other => other.to_string(),
    }
}

/// `params` as a scene file: the top-level keys, then each table, in declaration
/// order; unset optional values left out; `preset` first when given.
pub fn to_toml<P: ParamSet>(params: &P, preset: Option<&str>) -> Result<String> {
    let mut root = toml::Table::new();
    if let Some(p) = preset {
        root.insert("preset".to_owned(), toml::Value::String(p.to_owned()));
    }
    for param in P::params() {
        let Some(value) = params.get(param.key) else {
            continue;
        };
        if param.table.is_empty() {
            root.insert(param.key.to_owned(), value);
        } else {
            let table = root
                .entry(param.table.to_owned())
                .or_insert_with(|| toml::Value::Table(toml::Table::new()));
            if let toml::Value::Table(t) = table {
                t.insert(param.key.to_owned(), value);
            }
        }
    }
    toml::to_string(&root)
        .map_err(|e| Error::internal("--print-scene", format!("the scene as TOML: {e}")))
}

/// A scene file read: its preset (if any) and every key it sets, in file order, with
/// each key's line for messages.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SceneFile {
    /// `preset = "..."`.
    pub preset: Option<String>,
    /// (table, key, value, line): every parameter the file sets.
    pub values: Vec<(String, String, toml::Value, usize)>,
}

impl SceneFile {
    /// Parses a scene file's text for `P`: a syntax error, an unknown key or table, or
    /// a value of the wrong kind is refused with its (1-based) line.
    pub fn parse<P: ParamSet>(text: &str) -> Result<Self, (Option<usize>, String)> {
        let root: toml::Table = toml::from_str(text).map_err(|e| {
            let line = e
                .span()
                .map(|span| 1 + text[..span.start.min(text.len())].matches('\n').count());
            (line, cut(e.message().trim()))
        })?;
        let mut file = SceneFile::default();
        let known =
            |table: &str, key: &str| P::params().iter().any(|p| p.table == table && p.key == key);
        let tables: Vec<&str> = P::params()
            .iter()
            .map(|p| p.table)
            .filter(|t| !t.is_empty())
            .collect();
        for (key, value) in &root {
            match (key.as_str(), value) {
                ("preset", toml::Value::String(p)) => file.preset = Some(p.clone()),
                ("preset", _) => {
                    return Err((
                        line_of(text, "", "preset"),
                        "preset must be a name".to_owned(),
                    ));
                }
                (k, toml::Value::Table(inner)) if tables.contains(&k) => {
                    for (ik, iv) in inner {
                        if !known(k, ik) {
                            return Err((
                                line_of(text, k, ik),
                                format!("unknown key `{}` in [{k}]", crate::error::echo(ik)),
                            ));
                        }
                        file.values.push((
                            k.to_owned(),
                            ik.clone(),
                            iv.clone(),
                            line_of(text, k, ik).unwrap_or(0),
                        ));
                    }
                }
                (k, v) if known("", k) => {
                    file.values.push((
                        String::new(),
                        k.to_owned(),
                        v.clone(),
                        line_of(text, "", k).unwrap_or(0),
                    ));
                }
                (k, _) => {
                    return Err((
                        line_of(text, "", k),
                        format!("unknown key `{}`", crate::error::echo(k)),
                    ));
                }
            }
        }
        // Each value checked now, so a bad one is named with its line before any work.
        let mut probe = P::default();
        for (_, key, value, line) in &file.values {
            probe
                .set(key, Given::Toml(value))
                .map_err(|m| (Some(*line).filter(|l| *l > 0), format!("{key}: {m}")))?;
        }
        Ok(file)
    }

    /// Reads and parses `path`; errors name the file and line.
    pub fn read<P: ParamSet>(path: &Path) -> Result<Self> {
        let text = crate::input_files::read_text(
            path,
            "--scene",
            crate::input_files::InputKind::SceneFile,
        )?;
        Self::from_text::<P>(&path.display().to_string(), &text)
    }

    /// Parses `text`, a scene file called `name` in messages; errors name it and the
    /// line, quoting the line.
    pub fn from_text<P: ParamSet>(name: &str, text: &str) -> Result<Self> {
        Self::parse::<P>(text).map_err(|(line, message)| {
            let quoted = line
                .and_then(|l| text.lines().nth(l - 1))
                .map(|l| format!(" (`{}`)", crate::error::echo(l.trim())))
                .unwrap_or_default();
            Error::invalid(
                "--scene",
                match line {
                    Some(line) => format!("{name}:{line}: {message}{quoted}"),
                    None => format!("{name}: {message}"),
                },
            )
        })
    }

    /// Applies the file's values over `params`.
    pub fn apply<P: ParamSet>(&self, params: &mut P) -> Result<(), (usize, String)> {
        for (_, key, value, line) in &self.values {
            params
                .set(key, Given::Toml(value))
                .map_err(|m| (*line, format!("{key}: {m}")))?;
        }
        Ok(())
    }
}

/// A long message cut, as messages that quote input are.
fn cut(message: &str) -> String {
    match message.char_indices().nth(400) {
        Some((at, _)) => format!("{}...", &message[..at]),
        None => message.to_owned(),
    }
}

/// The (1-based) line where `key` is set in `table` ("" the top level) of a scene
/// file's text, or where the table of that name starts (a `[[key]]` array).
pub fn line_of(text: &str, table: &str, key: &str) -> Option<usize> {
    let mut current = String::new();
    for (i, line) in text.lines().enumerate() {
        let t = line.trim();
        if let Some(header) = t.strip_prefix("[[").and_then(|r| r.split("]]").next()) {
            if table.is_empty() && header.trim() == key {
                return Some(i + 1);
            }
            current = header.trim().to_owned();
            continue;
        }
        if let Some(header) = t.strip_prefix('[').and_then(|r| r.split(']').next()) {
            current = header.trim().to_owned();
            continue;
        }
        let name = t.split('=').next().map(str::trim).unwrap_or("");
        let name = name.trim_matches('"');
        if current == table && name == key && t.contains('=') {
            return Some(i + 1);
        }
    }
    None
}

/// `base` (a preset's parameters, or the defaults) with the scene file's and then the
/// command line's values applied over it, and validated; an error names the file and
/// line, or the key.
pub fn resolve<P: ParamSet>(
    base: P,
    file: Option<(&str, &SceneFile)>,
    given: &[(&'static str, String)],
) -> Result<P> {
    let mut params = base;
    if let Some((name, f)) = file {
        f.apply(&mut params)
            .map_err(|(line, m)| Error::invalid("--scene", format!("{name}:{line}: {m}")))?;
        params.validate().map_err(|e| match e {
            Error::InvalidArgument { argument, message } => Error::InvalidArgument {
                argument: format!("{argument} in {name}"),
                message,
            },
            other => other,
        })?;
    }
    for (key, text) in given {
        params
            .set(key, Given::Text(text))
            .map_err(|m| Error::invalid(*key, m))?;
    }
    params.validate()?;
    Ok(params)
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::str::FromStr;

    #[derive(Clone, Copy, Debug, PartialEq)]
    pub enum Colour {
        Red,
        Blue,
    }
    impl FromStr for Colour {
        type Err = Error;
        fn from_str(s: &str) -> Result<Self> {
            match s {
                "red" => Ok(Colour::Red),
                "blue" => Ok(Colour::Blue),
                other => Err(Error::invalid(
                    "--colour",
                    format!("\"{other}\" is not red or blue"),
                )),
            }
        }
    }
    impl Display for Colour {
        fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
            f.write_str(match self {
                Colour::Red => "red",
                Colour::Blue => "blue",
            })
        }
    }
    text_param!(Colour);

    fn cross(p: &Demo) -> Result<()> {
        if p.low > p.high {
            return Err(Error::invalid("low", "must not exceed high"));
        }
        Ok(())
    }

    params! {
        /// A demo set.
        pub struct Demo {
            /// How many, a count.
            [top, "Counts"] count: u32 = 9, "N", "", check::within(1..=256);
            /// The lower value.
            [top, "Values"] low: f32 = 0.5, "F", "m", check::at_least(0.0);
            /// The upper value.
            [top, "Values"] high: f32 = 2.0, "F", "m", check::above(0.0);
            /// A colour.
            [look, "Look"] colour: Colour = Colour::Red, "red|blue", "", check::any();
            /// A switch.
            [look, "Look"] shiny: bool = true, "on|off", "", check::any();
            /// Where the camera is.
            [camera, "Camera"] eye: Option<Point3> = None, "X,Y,Z", "m", check::any();
        }
        validate = cross;
    }

    #[test]
    fn rows_give_keys_tables_help_and_ranges() {
        let p = Demo::params();
        assert_eq!(p.len(), 6);
        assert_eq!(
            (p[0].key, p[0].table, p[0].range.as_str()),
            ("count", "", "1..=256")
        );
        assert_eq!(p[0].help, "How many, a count.");
        assert_eq!((p[3].table, p[3].flag()), ("look", "colour".to_owned()));
        assert_eq!(default_text::<Demo>("count"), "9");
        assert_eq!(default_text::<Demo>("shiny"), "on");
        assert_eq!(default_text::<Demo>("eye"), "none");
    }

    #[test]
    fn values_from_words_and_files_are_checked_and_named() {
        let file =
            "preset = \"x\"\ncount = 12\n[look]\ncolour = \"blue\"\n[camera]\neye = [1, 2.5, 3]\n";
        let parsed = SceneFile::parse::<Demo>(file).expect("parses");
        assert_eq!(parsed.preset.as_deref(), Some("x"));
        let mut d = Demo::default();
        parsed.apply(&mut d).expect("applies");
        assert_eq!(
            (d.count, d.colour, d.eye),
            (12, Colour::Blue, Some(Point3([1.0, 2.5, 3.0])))
        );
        // Unknown keys and bad values name their line.
        let bad = SceneFile::parse::<Demo>("count = 1\n[look]\nshine = true\n");
        assert_eq!(bad.map(drop).map_err(|(l, _)| l), Err(Some(3)));
        let bad = SceneFile::parse::<Demo>("\ncolour = 1\n");
        assert!(matches!(bad, Err((Some(2), _))), "{bad:?}");
        let bad = SceneFile::parse::<Demo>("[look]\ncolour = \"green\"\n");
        assert!(
            matches!(&bad, Err((Some(2), m)) if m.contains("green")),
            "{bad:?}"
        );
        // Non-finite numbers never get in.
        assert!(d.set("low", Given::Text("nan")).is_err());
        assert!(
            d.set("low", Given::Toml(&toml::Value::Float(f64::INFINITY)))
                .is_err()
        );
        // Ranges and the checks across parameters name the key.
        let named = |given: &[(&'static str, String)]| match resolve(Demo::default(), None, given) {
            Err(Error::InvalidArgument { argument, .. }) => argument,
            other => panic!("{other:?}"),
        };
        assert_eq!(named(&[("count", "0".into())]), "count");
        assert_eq!(named(&[("low", "3".into())]), "low");
        assert_eq!(named(&[("colour", "green".into())]), "colour");
    }

    #[test]
    fn print_and_read_back_give_the_same_values() {
        let d = Demo {
            count: 3,
            colour: Colour::Blue,
            eye: Some(Point3([0.0, 1.0, -2.0])),
            ..Demo::default()
        };
        let text = to_toml(&d, Some("p")).expect("toml");
        let parsed = SceneFile::parse::<Demo>(&text).expect("reads back");
        let mut back = Demo::default();
        parsed.apply(&mut back).expect("applies");
        assert_eq!(back, d, "{text}");
        assert!(text.starts_with("preset = \"p\""), "{text}");
    }
}
