//! THE list of terms of the rendering equation that photonmap computes (Jensen 2001, §9.1:
//! L = L_direct + L_specular + L_caustic + L_indirect, plus emission, the volume term and
//! the subsurface term).
//!
//! Every front end reads this list: the EXR writer, the CLI, the Python API and Blender's
//! `update_render_passes`. The combined image is the sum of all terms, exactly, per pixel.

/// One term, and one AOV.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
#[repr(u8)]
pub enum Term {
    /// Light from emitters reaching a non-specular surface seen directly, by next-event estimation.
    Direct = 0,
    /// Diffuse interreflection, from the global photon map by final gathering.
    Indirect = 1,
    /// Light focused by specular surfaces onto a diffuse one, from the caustic photon map.
    Caustic = 2,
    /// All light reaching the eye after at least one perfect mirror or refraction bounce.
    Specular = 3,
    /// Light scattered by participating media.
    Volume = 4,
    /// Emitters seen directly, and the background.
    Emission = 5,
    /// Light that left a surface after entering it below a subsurface material: what reaches
    /// a camera path's walk exits, from the lights and the photon maps.
    Subsurface = 6,
}

impl Term {
    /// In output order.
    pub const ALL: [Term; 7] = [
        Term::Direct,
        Term::Indirect,
        Term::Caustic,
        Term::Specular,
        Term::Volume,
        Term::Emission,
        Term::Subsurface,
    ];
    pub const COUNT: usize = 7;

    /// Lower-case name, used in files (`direct.R`) and on the command line.
    pub fn name(self) -> &'static str {
        match self {
            Term::Direct => "direct",
            Term::Indirect => "indirect",
            Term::Caustic => "caustic",
            Term::Specular => "specular",
            Term::Volume => "volume",
            Term::Emission => "emission",
            Term::Subsurface => "subsurface",
        }
    }

    /// Capitalised name, used as the Blender pass name.
    pub fn pass_name(self) -> &'static str {
        match self {
            Term::Direct => "Direct",
            Term::Indirect => "Indirect",
            Term::Caustic => "Caustic",
            Term::Specular => "Specular",
            Term::Volume => "Volume",
            Term::Emission => "Emission",
            Term::Subsurface => "Subsurface",
        }
    }

    pub fn index(self) -> usize {
        self as usize
    }

    pub fn bit(self) -> TermMask {
        TermMask(1 << self as u8)
    }

    pub fn from_name(name: &str) -> Option<Term> {
        Term::ALL.iter().copied().find(|t| t.name() == name)
    }
}

/// The AOV that is not a term: the estimated standard error of each pixel of the combined
/// image (per channel), from the spread of its samples or progressive passes. Files call it
/// `error`, Blender `Error`. It is not part of the sum.
pub const ERROR_AOV: &str = "error";
/// Blender pass name of [`ERROR_AOV`].
pub const ERROR_PASS: &str = "Error";

/// The denoising guide `albedo`: the reflectance of the first non-specular surface a camera
/// path reaches through perfect mirrors and glass, times their tint (Open Image Denoise's
/// albedo guide); Blender's `Denoising Albedo`.
pub const ALBEDO_AOV: &str = "albedo";
/// The denoising guide `normal`: the shading normal of that surface, facing the camera, in
/// camera space (x right, y up, z away from the camera, as Cycles writes it); Blender's
/// `Denoising Normal`.
pub const NORMAL_AOV: &str = "normal";
/// Suffix of a term's layer kept as rendered when the terms are denoised (`direct_noisy`).
pub const NOISY_SUFFIX: &str = "_noisy";
/// Layer-name prefix of a light group's image (`lightgroup.<name>`).
pub const LIGHTGROUP_PREFIX: &str = "lightgroup.";
pub use crate::scene::lightgroups::{light_group_names, DEFAULT_LIGHTGROUP};

/// The terms that `--denoise` denoises (each on its own; the beauty stays their sum).
/// `emission` (emitters and the background seen directly) is left as it is.
pub const DENOISED_TERMS: [Term; 6] = [
    Term::Direct,
    Term::Indirect,
    Term::Caustic,
    Term::Specular,
    Term::Volume,
    Term::Subsurface,
];

/// What the channels of an AOV hold.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum AovKind {
    /// Radiance or a colour: `R, G, B`.
    Color,
    /// A direction: `X, Y, Z`.
    Vector,
    /// Two Cryptomatte ranks: (id, coverage, id, coverage) as `R, G, B, A`.
    Crypto,
}

impl AovKind {
    /// The channel names, as suffixes of the layer name (`albedo.R`).
    pub fn channels(self) -> &'static [&'static str] {
        match self {
            AovKind::Color => &["R", "G", "B"],
            AovKind::Vector => &["X", "Y", "Z"],
            AovKind::Crypto => &["R", "G", "B", "A"],
        }
    }

    /// Blender's `chanid` of `RenderEngine.register_pass`.
    pub fn chan_id(self) -> &'static str {
        match self {
            AovKind::Color => "RGB",
            AovKind::Vector => "XYZ",
            AovKind::Crypto => "RGBA",
        }
    }

    /// Blender's pass type of `RenderEngine.register_pass`.
    pub fn pass_type(self) -> &'static str {
        match self {
            AovKind::Vector => "VECTOR",
            AovKind::Color | AovKind::Crypto => "COLOR",
        }
    }
}

/// One image written beside the terms, not part of their sum.
#[derive(Clone, Debug, PartialEq, Eq, serde::Serialize)]
pub struct AovSpec {
    /// The layer name in files and the key of Python's result (`albedo`,
    /// `lightgroup.key`, `CryptoObject00`).
    pub name: String,
    /// Blender's pass name (`Denoising Albedo`, `Combined_key`, `CryptoObject00`).
    pub pass_name: String,
    pub kind: AovKind,
}

impl AovSpec {
    fn new(name: impl Into<String>, pass_name: impl Into<String>, kind: AovKind) -> AovSpec {
        AovSpec {
            name: name.into(),
            pass_name: pass_name.into(),
            kind,
        }
    }

    pub fn channels(&self) -> &'static [&'static str] {
        self.kind.channels()
    }
}

/// Which Cryptomatte layers a render writes.
#[derive(
    Clone,
    Copy,
    Debug,
    Default,
    PartialEq,
    Eq,
    serde::Serialize,
    serde::Deserialize,
    clap::ValueEnum,
)]
#[serde(rename_all = "lowercase")]
pub enum Cryptomatte {
    /// Off: no Cryptomatte layers.
    #[default]
    Off,
    /// Object: `CryptoObject` mattes, one id per object (mesh or instance name).
    Object,
    /// Material: `CryptoMaterial` mattes, one id per material name.
    Material,
    /// Both: object and material mattes.
    Both,
}

impl Cryptomatte {
    pub fn object(self) -> bool {
        matches!(self, Cryptomatte::Object | Cryptomatte::Both)
    }
    pub fn material(self) -> bool {
        matches!(self, Cryptomatte::Material | Cryptomatte::Both)
    }
}

/// Cryptomatte's type name of the object mattes (the layer `CryptoObject00` ...).
pub const CRYPTO_OBJECT: &str = "CryptoObject";
/// Cryptomatte's type name of the material mattes.
pub const CRYPTO_MATERIAL: &str = "CryptoMaterial";

/// The optional AOVs a render is asked for (the settings `denoising_data`, `denoise`,
/// `cryptomatte`, `cryptomatte_levels`), and the scene's light groups.
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize)]
pub struct AovRequest {
    /// The denoising guides `albedo` and `normal`.
    pub denoising_data: bool,
    /// The terms are denoised; their noisy originals are kept as `<term>_noisy`.
    pub denoise: bool,
    pub cryptomatte: Cryptomatte,
    /// Cryptomatte ranks per pixel (two per layer).
    pub cryptomatte_levels: u32,
}

impl AovRequest {
    /// Whether the render records the guides: asked for, or needed by the denoiser.
    pub fn guides(&self) -> bool {
        self.denoising_data || self.denoise
    }

    /// Cryptomatte layers per type: ranks / 2, rounded up.
    pub fn crypto_layers(&self) -> usize {
        (self.cryptomatte_levels.max(1) as usize).div_ceil(2)
    }

    /// THE list of the AOVs beside the terms, in output order: `error`, then the denoising
    /// guides, the noisy terms, one image per light group (the groups sum to the beauty),
    /// and the Cryptomatte layers. Every front end writes what this list says.
    pub fn aovs(&self, light_groups: &[String]) -> Vec<AovSpec> {
        let mut out = vec![AovSpec::new(ERROR_AOV, ERROR_PASS, AovKind::Color)];
        if self.guides() {
            out.push(AovSpec::new(ALBEDO_AOV, "Denoising Albedo", AovKind::Color));
            out.push(AovSpec::new(
                NORMAL_AOV,
                "Denoising Normal",
                AovKind::Vector,
            ));
        }
        if self.denoise {
            for t in DENOISED_TERMS {
                out.push(AovSpec::new(
                    format!("{}{NOISY_SUFFIX}", t.name()),
                    format!("Noisy {}", t.pass_name()),
                    AovKind::Color,
                ));
            }
        }
        for g in light_groups {
            out.push(AovSpec::new(
                format!("{LIGHTGROUP_PREFIX}{g}"),
                format!("Combined_{g}"),
                AovKind::Color,
            ));
        }
        for (on, type_name) in [
            (self.cryptomatte.object(), CRYPTO_OBJECT),
            (self.cryptomatte.material(), CRYPTO_MATERIAL),
        ] {
            if on {
                for i in 0..self.crypto_layers() {
                    let n = format!("{type_name}{i:02}");
                    out.push(AovSpec::new(n.clone(), n, AovKind::Crypto));
                }
            }
        }
        out
    }
}

/// A set of terms: selects which estimators run.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub struct TermMask(pub u8);

impl TermMask {
    pub const NONE: TermMask = TermMask(0);
    pub const ALL: TermMask = TermMask(0b111_1111);

    pub fn contains(self, t: Term) -> bool {
        self.0 & t.bit().0 != 0
    }
    pub fn with(self, t: Term) -> TermMask {
        TermMask(self.0 | t.bit().0)
    }
    pub fn without(self, t: Term) -> TermMask {
        TermMask(self.0 & !t.bit().0)
    }
    pub fn iter(self) -> impl Iterator<Item = Term> {
        Term::ALL.into_iter().filter(move |t| self.contains(*t))
    }
}

/// Written as the list of its terms' names.
impl serde::Serialize for TermMask {
    fn serialize<S: serde::Serializer>(&self, ser: S) -> std::result::Result<S::Ok, S::Error> {
        ser.collect_seq(self.iter().map(Term::name))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_are_unique_and_round_trip() {
        for t in Term::ALL {
            assert_eq!(Term::from_name(t.name()), Some(t));
            assert_eq!(t.pass_name().to_lowercase(), t.name());
            assert_eq!(Term::ALL[t.index()], t);
        }
        let m = TermMask::NONE.with(Term::Caustic).with(Term::Direct);
        assert_eq!(
            m.iter().collect::<Vec<_>>(),
            vec![Term::Direct, Term::Caustic]
        );
        assert!(!m.without(Term::Direct).contains(Term::Direct));
    }

    #[test]
    fn the_aov_list_holds_what_is_asked_for_and_nothing_else() {
        let names = |r: &AovRequest, g: &[String]| -> Vec<String> {
            r.aovs(g).into_iter().map(|a| a.name).collect()
        };
        let none = AovRequest::default();
        assert_eq!(names(&none, &[]), vec!["error"]);
        let all = AovRequest {
            denoising_data: false,
            denoise: true,
            cryptomatte: Cryptomatte::Both,
            cryptomatte_levels: 6,
        };
        let groups = vec!["key".to_string(), DEFAULT_LIGHTGROUP.to_string()];
        let list = all.aovs(&groups);
        let got: Vec<&str> = list.iter().map(|a| a.name.as_str()).collect();
        assert_eq!(
            got,
            vec![
                "error",
                "albedo",
                "normal",
                "direct_noisy",
                "indirect_noisy",
                "caustic_noisy",
                "specular_noisy",
                "volume_noisy",
                "subsurface_noisy",
                "lightgroup.key",
                "lightgroup.default",
                "CryptoObject00",
                "CryptoObject01",
                "CryptoObject02",
                "CryptoMaterial00",
                "CryptoMaterial01",
                "CryptoMaterial02",
            ]
        );
        let pass = |n: &str| list.iter().find(|a| a.name == n).unwrap().pass_name.clone();
        assert_eq!(pass("albedo"), "Denoising Albedo");
        assert_eq!(pass("normal"), "Denoising Normal");
        assert_eq!(pass("lightgroup.key"), "Combined_key");
        assert_eq!(pass("direct_noisy"), "Noisy Direct");
        assert_eq!(list[2].channels(), ["X", "Y", "Z"]);
        assert_eq!(list[11].channels(), ["R", "G", "B", "A"]);
        // Names and pass names are unique.
        let mut n: Vec<_> = list.iter().map(|a| &a.pass_name).collect();
        n.sort();
        n.dedup();
        assert_eq!(n.len(), list.len());
        // Seven levels take four layers.
        let odd = AovRequest {
            cryptomatte: Cryptomatte::Object,
            cryptomatte_levels: 7,
            ..AovRequest::default()
        };
        assert_eq!(odd.aovs(&[]).len(), 5);
    }
}
