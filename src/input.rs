//! Keys the viewer understands, independent of the window system, and the
//! `--script` of synthesised key presses that tests (and demos) feed through the same
//! handler as real ones.

use crate::error::{Error, Result};

/// A key press as the viewer sees it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Key {
    /// A printable character (letters lower-case).
    Char(char),
    /// The space bar (pause and resume the growth).
    Space,
    /// Tab (the orbit / fly camera).
    Tab,
    /// Return.
    Enter,
    /// Escape (quit).
    Escape,
    /// The left arrow.
    Left,
    /// The right arrow.
    Right,
    /// The up arrow.
    Up,
    /// The down arrow.
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

/// A synthesised input.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Scripted {
    /// A key press (and release) as the user would type it.
    Key(Key),
    /// Ask the window system for this inner size (as a user dragging the border).
    Resize(u32, u32),
}

/// One synthesised input before frame `frame` (0-based).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ScriptedKey {
    /// The frame it comes before, counted from 0.
    pub frame: u32,
    /// What happens then.
    pub input: Scripted,
}

/// Parses `FRAME:KEY[,FRAME:KEY...]`, e.g. `10:c,10:c,40:space`; `FRAME:resize=WxH`
/// resizes the window.
pub fn parse_script(text: &str) -> Result<Vec<ScriptedKey>> {
    let mut out = Vec::new();
    for item in text.split(',').map(str::trim).filter(|s| !s.is_empty()) {
        let (frame, key) = item
            .split_once(':')
            .ok_or_else(|| Error::invalid("--script", format!("\"{item}\" is not FRAME:KEY")))?;
        let frame = frame.trim().parse::<u32>().map_err(|_| {
            Error::invalid("--script", format!("\"{frame}\" is not a frame number"))
        })?;
        // "," itself cannot be scripted (it separates items); "comma" names it.
        let input = if key.trim() == "comma" {
            Scripted::Key(Key::Char(','))
        } else if let Some(size) = key.trim().strip_prefix("resize=") {
            let (w, h) = size
                .split_once('x')
                .and_then(|(w, h)| Some((w.parse::<u32>().ok()?, h.parse::<u32>().ok()?)))
                .filter(|&(w, h)| (1..=16384).contains(&w) && (1..=16384).contains(&h))
                .ok_or_else(|| {
                    Error::invalid("--script", format!("\"{size}\" is not WxH in 1..=16384"))
                })?;
            Scripted::Resize(w, h)
        } else {
            Scripted::Key(key.trim().parse()?)
        };
        out.push(ScriptedKey { frame, input });
    }
    out.sort_by_key(|k| k.frame);
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn scripts_parse_in_frame_order_and_bad_ones_name_the_option() {
        let s = parse_script("20:space, 5:C,5:f2,7:comma,9:resize=64x48").expect("script");
        let at = |frame, input| ScriptedKey { frame, input };
        assert_eq!(
            s,
            vec![
                at(5, Scripted::Key(Key::Char('c'))),
                at(5, Scripted::Key(Key::F(2))),
                at(7, Scripted::Key(Key::Char(','))),
                at(9, Scripted::Resize(64, 48)),
                at(20, Scripted::Key(Key::Space)),
            ]
        );
        for bad in ["x", "1:", "a:b", "3:shift", "3:resize=0x4", "3:resize=9"] {
            let e = parse_script(bad).expect_err(bad).to_string();
            assert!(e.contains("--script"), "{e}");
        }
    }
}
