//! Keys the viewer understands, independent of the window system, and the
//! `--script` of synthesised key presses that tests (and demos) feed through the same
//! handler as real ones.

use crate::error::{Error, Result};

/// A key press as the viewer sees it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Key {
    /// A printable character (letters lower-case).
    Char(char),
    Space,
    Tab,
    Enter,
    Escape,
    Left,
    Right,
    Up,
    Down,
    /// F1..F12.
    F(u8),
}

impl std::str::FromStr for Key {
    type Err = Error;

    fn from_str(s: &str) -> Result<Self> {
        let lower = s.to_ascii_lowercase();
        Ok(match lower.as_str() {
            "space" => Key::Space,
            "tab" => Key::Tab,
            "enter" => Key::Enter,
            "esc" | "escape" => Key::Escape,
            "left" => Key::Left,
            "right" => Key::Right,
            "up" => Key::Up,
            "down" => Key::Down,
            f if f.len() >= 2 && f.starts_with('f') && f[1..].parse::<u8>().is_ok() => {
                Key::F(f[1..].parse::<u8>().unwrap_or(1))
            }
            c if c.chars().count() == 1 => Key::Char(c.chars().next().unwrap_or(' ')),
            _ => {
                return Err(Error::invalid(
                    "--script",
                    format!(
                        "\"{s}\" is not a key (a character, space, tab, enter, esc, left, \
                         right, up, down or f1..f12)"
                    ),
                ));
            }
        })
    }
}

/// One synthesised key press before frame `frame` (0-based).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ScriptedKey {
    pub frame: u32,
    pub key: Key,
}

/// Parses `FRAME:KEY[,FRAME:KEY...]`, e.g. `10:c,10:c,40:space`.
pub fn parse_script(text: &str) -> Result<Vec<ScriptedKey>> {
    let mut out = Vec::new();
    for item in text.split(',').map(str::trim).filter(|s| !s.is_empty()) {
        let (frame, key) = item.split_once(':').ok_or_else(|| {
            Error::invalid("--script", format!("\"{item}\" is not FRAME:KEY"))
        })?;
        let frame = frame.trim().parse::<u32>().map_err(|_| {
            Error::invalid("--script", format!("\"{frame}\" is not a frame number"))
        })?;
        // "," itself cannot be scripted (it separates items); "comma" names it.
        let key = if key.trim() == "comma" {
            Key::Char(',')
        } else {
            key.trim().parse()?
        };
        out.push(ScriptedKey { frame, key });
    }
    out.sort_by_key(|k| k.frame);
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn scripts_parse_in_frame_order_and_bad_ones_name_the_option() {
        let s = parse_script("20:space, 5:C,5:f2,7:comma").expect("script");
        assert_eq!(
            s,
            vec![
                ScriptedKey { frame: 5, key: Key::Char('c') },
                ScriptedKey { frame: 5, key: Key::F(2) },
                ScriptedKey { frame: 7, key: Key::Char(',') },
                ScriptedKey { frame: 20, key: Key::Space },
            ]
        );
        for bad in ["x", "1:", "a:b", "3:shift"] {
            let e = parse_script(bad).expect_err(bad).to_string();
            assert!(e.contains("--script"), "{e}");
        }
    }
}
