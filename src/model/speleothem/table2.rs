//! Tortelli & Walter's growth parameters (section 4.1, Table 2) and mineral colours
//! (Table 1).

use std::fmt;
use std::str::FromStr;

use crate::error::Error;

/// Pluviometric index level: how much rain reaches the cave.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Pil {
    /// Level 0: no rain, no growth.
    Dry = 0,
    /// Level 1: stalactites grow; drops solidify at the tip or on the flank, none fall.
    Stalactites = 1,
    /// Level 2: drops fall, so stalagmites grow under the stalactites.
    Dripping = 2,
}

/// Drip interval (inversely related to the pluviometric index).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum DripInterval {
    /// Long interval: new stalagmite rings narrow.
    Dry,
    /// The ring keeps its radius.
    Standard,
    /// Short interval: new stalagmite rings widen.
    Wet,
}

/// Calcium / CO2 concentration of the drop: drives the height step.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Co2 {
    /// Height step x1; stalactite rings narrow by 2 radius units; drops may solidify
    /// on the flank.
    Low,
    /// Height step x2; stalactite rings narrow by 1 radius unit.
    Normal,
    /// Height step x3; stalactite rings keep their radius.
    High,
}

/// Mineral mixed into the solution (Table 1 colours).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Mineral {
    /// Plain calcite: light grey (0.8, 0.8, 0.8).
    Calcareous,
    /// Iron: ochre brown.
    Iron,
    /// Manganese: slate blue-grey.
    Manganese,
    /// Copper: turquoise.
    Copper,
    /// Malachite: pale green.
    Malachite,
}

impl Mineral {
    /// Table 1: mineral colour `mc` (RGB).
    pub fn color(self) -> [f32; 3] {
        match self {
            Mineral::Calcareous => [0.8, 0.8, 0.8],
            Mineral::Iron => [0.87, 0.62, 0.34],
            Mineral::Manganese => [0.32, 0.44, 0.54],
            Mineral::Copper => [0.05, 0.7, 0.7],
            Mineral::Malachite => [0.67, 0.82, 0.75],
        }
    }

    /// The mineral colour as the linear-light albedo the shaders use. Table 1's colours
    /// are display values (the paper's Direct3D 10 renderer shaded in display space,
    /// with no sRGB target): used as linear albedo through an sRGB target they display
    /// paler (malachite's saturation 0.18 shows as 0.08). So each is decoded from sRGB
    /// and scaled so that calcareous keeps the 0.8 albedo of white calcite.
    pub fn albedo(self) -> [f32; 3] {
        let decode = crate::model::srgb::srgb_to_linear;
        let white = Mineral::Calcareous.color()[0];
        let scale = white / decode(white);
        self.color().map(|c| (decode(c) * scale).min(1.0))
    }

    /// Every mineral, in declaration order (for listing them).
    pub const ALL: [Mineral; 5] = [
        Mineral::Calcareous,
        Mineral::Iron,
        Mineral::Manganese,
        Mineral::Copper,
        Mineral::Malachite,
    ];
}

/// Radius and height steps of one Table 2 row, in multiples of the scene's units
/// (negative radius: the new ring is narrower).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StepMultiples {
    /// Change of the ring radius, in radius units (-2 to 1).
    pub radius: f32,
    /// Height of the new band along the growth, in height units (1 to 3).
    pub height: f32,
}

/// Table 2 for stalactites (its PIL 1 rows). sediment applies them at PIL 2 as well:
/// dripping makes stalagmites possible, it does not stop the stalactites above.
pub fn stalactite_steps(co2: Co2) -> StepMultiples {
    match co2 {
        Co2::Low => StepMultiples {
            radius: -2.0,
            height: 1.0,
        },
        Co2::Normal => StepMultiples {
            radius: -1.0,
            height: 2.0,
        },
        Co2::High => StepMultiples {
            radius: 0.0,
            height: 3.0,
        },
    }
}

/// Table 2 for stalagmites (its PIL 2 rows): the drip interval sets the radius step,
/// the CO2 concentration the height step.
pub fn stalagmite_steps(drip: DripInterval, co2: Co2) -> StepMultiples {
    let radius = match drip {
        DripInterval::Dry => -1.0,
        DripInterval::Standard => 0.0,
        DripInterval::Wet => 1.0,
    };
    let height = match co2 {
        Co2::Low => 1.0,
        Co2::Normal => 2.0,
        Co2::High => 3.0,
    };
    StepMultiples { radius, height }
}

macro_rules! named_enum {
    ($ty:ty, $what:literal, [$($name:literal => $value:expr),+ $(,)?]) => {
        impl FromStr for $ty {
            type Err = Error;
            fn from_str(s: &str) -> Result<Self, Error> {
                match s.trim().to_ascii_lowercase().as_str() {
                    $($name => Ok($value),)+
                    other => Err(Error::invalid(
                        $what,
                        format!(
                            "\"{other}\" is not one of: {}",
                            [$($name),+].join(", ")
                        ),
                    )),
                }
            }
        }
        impl fmt::Display for $ty {
            fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                let name = match self { $(v if *v == $value => $name,)+ _ => "?" };
                f.write_str(name)
            }
        }
    };
}

crate::serde_as_text!(Pil, DripInterval, Co2, Mineral);

named_enum!(Pil, "pluviometric index (--pil)", ["0" => Pil::Dry, "1" => Pil::Stalactites, "2" => Pil::Dripping]);
named_enum!(DripInterval, "drip interval (--drip)", ["dry" => DripInterval::Dry, "standard" => DripInterval::Standard, "wet" => DripInterval::Wet]);
named_enum!(Co2, "CO2 concentration (--co2)", ["low" => Co2::Low, "normal" => Co2::Normal, "high" => Co2::High]);
named_enum!(Mineral, "mineral (--mineral)", [
    "calcareous" => Mineral::Calcareous,
    "iron" => Mineral::Iron,
    "manganese" => Mineral::Manganese,
    "copper" => Mineral::Copper,
    "malachite" => Mineral::Malachite,
]);

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn table2_rows() {
        assert_eq!(
            stalactite_steps(Co2::Low),
            StepMultiples {
                radius: -2.0,
                height: 1.0
            }
        );
        assert_eq!(
            stalactite_steps(Co2::Normal),
            StepMultiples {
                radius: -1.0,
                height: 2.0
            }
        );
        assert_eq!(
            stalactite_steps(Co2::High),
            StepMultiples {
                radius: 0.0,
                height: 3.0
            }
        );
        for (co2, h) in [(Co2::Low, 1.0), (Co2::Normal, 2.0), (Co2::High, 3.0)] {
            for (drip, r) in [
                (DripInterval::Dry, -1.0),
                (DripInterval::Standard, 0.0),
                (DripInterval::Wet, 1.0),
            ] {
                assert_eq!(
                    stalagmite_steps(drip, co2),
                    StepMultiples {
                        radius: r,
                        height: h
                    }
                );
            }
        }
    }

    #[test]
    fn names_parse_and_reject() {
        assert_eq!("2".parse::<Pil>().ok(), Some(Pil::Dripping));
        assert_eq!("Wet".parse::<DripInterval>().ok(), Some(DripInterval::Wet));
        assert_eq!(
            "malachite".parse::<Mineral>().ok(),
            Some(Mineral::Malachite)
        );
        assert_eq!(Mineral::Iron.to_string(), "iron");
        assert_eq!(Mineral::Calcareous.albedo(), Mineral::Calcareous.color());
        for m in Mineral::ALL {
            let (c, a) = (m.color(), m.albedo());
            // Decoding keeps the order of the channels (the hue's sextant) and
            // saturates: the darkest channel falls relative to the brightest.
            let order = |v: [f32; 3]| v[0] <= v[1] && v[1] <= v[2];
            assert_eq!(order(c), order(a), "{m}");
            let sat = |v: [f32; 3]| {
                1.0 - v.iter().fold(1f32, |x, y| x.min(*y)) / v.iter().fold(0f32, |x, y| x.max(*y))
            };
            assert!(sat(a) >= sat(c) - 1e-6, "{m}");
        }
        let err = "3"
            .parse::<Pil>()
            .expect_err("PIL 3 does not exist")
            .to_string();
        assert!(err.contains("--pil") && err.contains("0, 1, 2"), "{err}");
        let err = "gold".parse::<Mineral>().expect_err("no gold").to_string();
        assert!(err.contains("gold") && err.contains("malachite"), "{err}");
    }
}
