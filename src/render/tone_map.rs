//! The tone-mapping operators of `shaders-glsl/common/tonemap.glsl`: which one a
//! pipeline applies is fixed when it is built (specialization constants), since
//! llvmpipe runs every side of a branch on a uniform.

use crate::error::{Error, Result};

/// The tone-mapping operator (`tonemap.glsl`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum ToneMap {
    /// Narkowicz's fit of the ACES filmic curve, per channel.
    #[default]
    Aces,
    /// Reinhard's `L / (1 + L)` on luminance.
    Reinhard,
    /// Ashikhmin's (2002) global operator on luminance, which Tortelli & Walter cite.
    Ashikhmin,
    /// None: radiance times exposure, for floating-point targets (the environment
    /// map's faces); not offered to users.
    Linear,
}

impl ToneMap {
    /// The specialization constants that pick the operator in `tonemap.glsl`
    /// (`constant_id` 16 Reinhard, 17 Ashikhmin, 18 linear; none set is ACES), for
    /// `GraphicsPipelineDesc::specialize`. Every pipeline that tone-maps is built for
    /// one operator.
    pub fn constants(self) -> [(u32, u32); 3] {
        [
            (16, u32::from(self == ToneMap::Reinhard)),
            (17, u32::from(self == ToneMap::Ashikhmin)),
            (18, u32::from(self == ToneMap::Linear)),
        ]
    }

    /// The operators users may choose (`--tonemap`; not `Linear`), in the order the
    /// viewer's key cycles through them.
    pub const ALL: [ToneMap; 3] = [ToneMap::Ashikhmin, ToneMap::Aces, ToneMap::Reinhard];
}

impl std::fmt::Display for ToneMap {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            ToneMap::Aces => "aces",
            ToneMap::Reinhard => "reinhard",
            ToneMap::Ashikhmin => "ashikhmin",
            ToneMap::Linear => "linear",
        })
    }
}

impl std::str::FromStr for ToneMap {
    type Err = Error;
    fn from_str(s: &str) -> Result<Self> {
        match s.trim().to_ascii_lowercase().as_str() {
            "aces" => Ok(ToneMap::Aces),
            "reinhard" => Ok(ToneMap::Reinhard),
            "ashikhmin" => Ok(ToneMap::Ashikhmin),
            other => Err(Error::invalid(
                "--tonemap",
                format!("\"{other}\" is not one of: ashikhmin, aces, reinhard"),
            )),
        }
    }
}

crate::serde_as_text!(ToneMap);
