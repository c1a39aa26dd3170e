//! THE list of terms of the rendering equation that photonmap computes (Jensen 2001, §9.1:
//! L = L_direct + L_specular + L_caustic + L_indirect, plus emission and the volume term).
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
}

impl Term {
    /// In output order.
    pub const ALL: [Term; 6] = [
        Term::Direct,
        Term::Indirect,
        Term::Caustic,
        Term::Specular,
        Term::Volume,
        Term::Emission,
    ];
    pub const COUNT: usize = 6;

    /// Lower-case name, used in files (`direct.R`) and on the command line.
    pub fn name(self) -> &'static str {
        match self {
            Term::Direct => "direct",
            Term::Indirect => "indirect",
            Term::Caustic => "caustic",
            Term::Specular => "specular",
            Term::Volume => "volume",
            Term::Emission => "emission",
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

/// A set of terms: selects which estimators run.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub struct TermMask(pub u8);

impl TermMask {
    pub const NONE: TermMask = TermMask(0);
    pub const ALL: TermMask = TermMask(0b11_1111);

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
}
