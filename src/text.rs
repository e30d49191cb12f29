//! Values that are read and written as the text the command line takes — a name
//! (`"iron"`, `"dune+ripple"`, `"off"`) or a number (`pil = 2`, `repose = 33`) — in
//! scene files too: serde through the type's `FromStr` and `Display`, so each such type
//! has one spelling everywhere.

/// Implements serde's `Serialize` and `Deserialize` for types with `Display` and
/// `FromStr`: written as a number when the text is one, else as a string; read from a
/// string or a number, with the type's own error message.
#[macro_export]
macro_rules! serde_as_text {
    ($($ty:ty),+ $(,)?) => {$(
        impl serde::Serialize for $ty {
            fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
                $crate::text::serialize(&self.to_string(), s)
            }
        }
        impl<'de> serde::Deserialize<'de> for $ty {
            fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
                let text = $crate::text::deserialize(d)?;
                text.parse().map_err(|e: $crate::Error| {
                    <D::Error as serde::de::Error>::custom(match e {
                        $crate::Error::InvalidArgument { argument, message } => {
                            format!("{argument}: {message}")
                        }
                        other => other.to_string(),
                    })
                })
            }
        }
    )+};
}

/// Writes `text` as an integer or a float when it is one, else as a string.
pub fn serialize<S: serde::Serializer>(text: &str, s: S) -> Result<S::Ok, S::Error> {
    if let Ok(n) = text.parse::<u64>() {
        s.serialize_u64(n)
    } else if let Ok(x) = text.parse::<f64>() {
        s.serialize_f64(x)
    } else {
        s.serialize_str(text)
    }
}

/// Reads a string, an integer or a float as text.
pub fn deserialize<'de, D: serde::Deserializer<'de>>(d: D) -> Result<String, D::Error> {
    struct Text;
    impl serde::de::Visitor<'_> for Text {
        type Value = String;
        fn expecting(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
            f.write_str("a name or a number")
        }
        fn visit_str<E: serde::de::Error>(self, v: &str) -> Result<String, E> {
            Ok(v.to_owned())
        }
        fn visit_u64<E: serde::de::Error>(self, v: u64) -> Result<String, E> {
            Ok(v.to_string())
        }
        fn visit_i64<E: serde::de::Error>(self, v: i64) -> Result<String, E> {
            Ok(v.to_string())
        }
        fn visit_f64<E: serde::de::Error>(self, v: f64) -> Result<String, E> {
            Ok(v.to_string())
        }
    }
    d.deserialize_any(Text)
}

/// `x` as the `f64` whose shortest decimal is `x`'s own (`0.001_f32` is `0.001`, not
/// `0.0010000000474974513`): for JSON reports of values the models hold as `f32`.
pub fn json_f32(x: f32) -> f64 {
    x.to_string().parse().unwrap_or(f64::from(x))
}
