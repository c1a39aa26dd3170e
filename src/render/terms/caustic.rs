//! `caustic`: light focused by mirrors and glass onto a non-specular surface, visualised
//! directly from the caustic photon map with a cone filter (Jensen 2001, §9.1, §7.2.2).

use crate::geometry::SurfaceInteraction;
use crate::materials::bsdf::Bsdf;
use crate::math::Spectrum;
use crate::photon::map::{EstimateFilter, GroupShare, Select};
use crate::photon::KnnScratch;
use crate::render::lightgroups::Split;
use crate::render::photons::PhotonMaps;

/// Jensen's cone-filter constant.
pub const CONE_K: f32 = 1.1;

/// The caustic radiance at `si`; each light group's share (the photons' groups) goes to
/// `split`.
pub fn estimate(
    maps: &PhotonMaps,
    si: &SurfaceInteraction,
    bsdf: &Bsdf,
    scratch: &mut KnnScratch,
    split: Option<&mut Split>,
) -> Spectrum {
    match &maps.caustic {
        Some(m) => {
            let mut share = split.map(|sp| move |g: usize, v: Spectrum| sp.add(g, v));
            m.radiance(
                si.p,
                si.ng,
                si.wo,
                bsdf,
                maps.gather,
                maps.caustic_r2,
                EstimateFilter::Cone { k: CONE_K },
                Select::ALL,
                scratch,
                share.as_mut().map(|f| f as GroupShare),
            )
        }
        None => Spectrum::ZERO,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::PI;
    use crate::photon::map::{MapKind, PhotonMap, PhotonTree};
    use crate::photon::{Photon, PhotonKdTree};
    use crate::render::terms::testing;
    use crate::scene::Scene;
    use glam::Vec3;

    const RHO: f32 = 0.5;
    /// Photon spacing and power: a flux density of POWER / SPACING² = 2.5 W/m².
    const SPACING: f32 = 0.02;
    const POWER: f32 = 0.001;

    fn floor() -> Scene {
        testing::scene(serde_json::json!({
            "materials": [{"type": "diffuse", "name": "grey", "color": [RHO, RHO, RHO]}],
            "meshes": [testing::floor(0)],
        }))
    }

    /// A caustic map of photons falling straight down on a square grid over x in [-2, x_max),
    /// y in [-2, 2), each carrying `power`.
    fn maps(x_max: f32, power: f32) -> PhotonMaps {
        let mut photons = Vec::new();
        let n = (4.0 / SPACING) as i32;
        for i in 0..n {
            for j in 0..n {
                let p = Vec3::new(
                    -2.0 + (i as f32 + 0.5) * SPACING,
                    -2.0 + (j as f32 + 0.5) * SPACING,
                    0.0,
                );
                if p.x < x_max {
                    photons.push(Photon::new(p, Vec3::splat(power), -Vec3::Z).unwrap());
                }
            }
        }
        let map = PhotonMap {
            kind: MapKind::Caustic,
            tree: PhotonTree::Rgbe(PhotonKdTree::build(photons), 1.0),
            irradiance: None,
            exitance: None,
            emitted: 1,
            build_seconds: 0.0,
        };
        PhotonMaps {
            global: None,
            caustic: Some(map),
            volume: None,
            volume_points: None,
            gather: 200,
            global_r2: 0.25,
            caustic_r2: 0.25,
        }
    }

    fn at(sc: &Scene, maps: &PhotonMaps, x: f32) -> f32 {
        let (si, bsdf) = testing::hit_below(sc, x);
        estimate(maps, &si, &bsdf, &mut KnnScratch::default(), None).x
    }

    #[test]
    fn a_uniform_photon_density_gives_rho_over_pi_times_the_flux_density() {
        let sc = floor();
        let expected = RHO / PI * POWER / (SPACING * SPACING);
        let xs = [-1.013, -0.5, -0.271, 0.0, 0.137, 0.6, 1.0];
        let mean_of = |m: &PhotonMaps| xs.iter().map(|&x| at(&sc, m, x)).sum::<f32>() / 7.0;
        let m = maps(2.0, POWER);
        for x in xs {
            let got = at(&sc, &m, x);
            assert!(
                (got / expected - 1.0).abs() < 0.03,
                "x {x}: {got} against {expected}"
            );
        }
        let mean = mean_of(&m);
        assert!(
            (mean / expected - 1.0).abs() < 0.01,
            "{mean} against {expected}"
        );
        // Photons 2% brighter are told apart.
        let brighter = mean_of(&maps(2.0, POWER * 1.02));
        assert!(
            brighter / expected - 1.0 > 0.01,
            "{brighter} against {expected}"
        );
    }

    #[test]
    fn a_caustic_edge_stays_within_the_gather_radius() {
        // Photons on x < 0 only: full density a radius inside, none a radius outside.
        let sc = floor();
        let m = maps(0.0, POWER);
        let expected = RHO / PI * POWER / (SPACING * SPACING);
        let r = (m.gather as f32 / PI).sqrt() * SPACING;
        assert!((at(&sc, &m, -1.5 * r) / expected - 1.0).abs() < 0.03);
        assert_eq!(at(&sc, &m, 0.6), 0.0);
        let edge = at(&sc, &m, 0.0);
        assert!(edge > 0.2 * expected && edge < 0.8 * expected, "{edge}");
    }

    #[test]
    fn no_caustic_map_gives_nothing() {
        let sc = floor();
        let mut m = maps(2.0, POWER);
        m.caustic = None;
        assert_eq!(at(&sc, &m, 0.0), 0.0);
    }
}
