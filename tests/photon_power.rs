//! Photon power as Ward's RGBE (20-byte photons, the default) against `f32` power (28 bytes):
//! the same photons, the same image up to the RGBE quantisation, and memory that follows the
//! record size in the stats, the estimate and the memory-limit check.

use crate::common;

use common::{load_scene, render_settings};
use photonmap::cli::{Cli, Command};
use photonmap::render::aov::Term;
use photonmap::render::film::Image;
use photonmap::render::settings::{Bytes, FilterName, PhotonPower};
use photonmap::render::settings::{BYTES_PER_PHOTON, BYTES_PER_PHOTON_F32};
use photonmap::render::{RenderOutput, RenderSettings, Renderer};
use photonmap::scene::{Scene, SceneDesc};

fn small_spheres() -> SceneDesc {
    let mut desc = load_scene("cornell_spheres");
    desc.film.width = 48;
    desc.film.height = 48;
    desc
}

fn settings(f32_power: bool) -> RenderSettings {
    RenderSettings {
        spp: 4,
        seed: 5,
        threads: 2,
        filter: FilterName::Box,
        photons: 30_000,
        caustic_photons: 20_000,
        final_gather_rays: 64,
        photon_power: if f32_power {
            PhotonPower::F32
        } else {
            PhotonPower::Rgbe
        },
        ..Default::default()
    }
}

/// Relative L1 difference: sum |a - b| / sum |b| over pixels and channels.
fn rel_l1(a: &Image, b: &Image) -> f64 {
    let (mut d, mut n) = (0.0f64, 0.0f64);
    for (p, q) in a.data.iter().zip(&b.data) {
        for c in 0..3 {
            d += (p[c] - q[c]).abs() as f64;
            n += q[c].abs() as f64;
        }
    }
    d / n
}

fn map_bytes(out: &RenderOutput, map: &str) -> (u64, u64, u64) {
    let m = out
        .stats
        .photon_maps
        .iter()
        .find(|m| m.map == map && m.built)
        .unwrap_or_else(|| panic!("{map} map built"));
    // The global map also holds its precomputed irradiance points, 20 B each.
    (
        m.stored,
        m.memory_bytes - 20 * m.irradiance_points,
        m.bytes_per_photon,
    )
}

/// Both encodings store the same photons (RGBE quantises only the power), so the images differ
/// only by the quantisation: at most 1/256 of a photon's largest channel, with either sign,
/// which averages out over the ~100 photons of an estimate. Tolerance: mean relative
/// difference below 0.5% for the combined image and for the photon-map terms (`indirect`,
/// `caustic`), and the images must differ at all (the setting reaches the maps).
#[test]
fn f32_and_rgbe_power_give_the_same_image_within_quantisation() {
    let desc = small_spheres();
    let rgbe = render_settings(&desc, settings(false));
    let f32p = render_settings(&desc, settings(true));
    for map in ["global", "caustic"] {
        let (n_rgbe, bytes_rgbe, per_rgbe) = map_bytes(&rgbe, map);
        let (n_f32, bytes_f32, per_f32) = map_bytes(&f32p, map);
        assert_eq!(n_rgbe, n_f32, "{map}: same photons stored");
        assert_eq!(per_rgbe, 20);
        assert_eq!(per_f32, 28);
        assert_eq!(bytes_rgbe, 20 * n_rgbe, "{map}");
        assert_eq!(bytes_f32, 28 * n_f32, "{map}");
    }
    assert_eq!(rgbe.stats.bytes_per_photon, 20);
    assert_eq!(f32p.stats.bytes_per_photon, 28);
    let combined = rel_l1(&f32p.film.combined(), &rgbe.film.combined());
    let indirect = rel_l1(
        f32p.film.term(Term::Indirect),
        rgbe.film.term(Term::Indirect),
    );
    let caustic = rel_l1(f32p.film.term(Term::Caustic), rgbe.film.term(Term::Caustic));
    let direct = rel_l1(f32p.film.term(Term::Direct), rgbe.film.term(Term::Direct));
    eprintln!(
        "f32 vs RGBE power, mean relative difference: combined {combined:.2e}, indirect \
         {indirect:.2e}, caustic {caustic:.2e}, direct {direct:.2e}"
    );
    assert!(combined < 5e-3, "combined {combined}");
    assert!(indirect < 5e-3, "indirect {indirect}");
    assert!(caustic < 5e-3, "caustic {caustic}");
    assert!(combined > 0.0, "the power encoding changed nothing");
    // Direct light does not read the photon maps; it can differ only where a pixel's random
    // stream took another turn (an irradiance-cache record of another reach, so a gather
    // ray more or fewer, before a later specular bounce's direct estimate).
    assert!(direct < 1e-4, "direct {direct}");
}

/// The memory estimate and the memory limit use the record size of the setting.
#[test]
fn memory_estimate_follows_the_photon_size() {
    let desc = load_scene("cornell_diffuse");
    let scene = Scene::build(&desc).unwrap();
    assert_eq!(BYTES_PER_PHOTON, 20);
    assert_eq!(BYTES_PER_PHOTON_F32, 28);
    for (f32_power, size) in [(false, 20), (true, 28)] {
        let mut s = settings(f32_power);
        s.photons = 1_000_000;
        assert_eq!(s.bytes_per_photon(), size);
        let est = Renderer::new(&scene).settings(s.clone()).memory_estimate();
        // No specular surfaces, no media: the global map only.
        assert_eq!(est.photons, 1_000_000);
        assert_eq!(est.photon_bytes, size * 1_000_000);
        // Photons are traced as their records (the power scale divides by the paths emitted
        // as they are read) and the kd-tree is balanced in place: the peak is the map. A
        // limit one byte under the peak fails, naming the record size.
        assert_eq!(est.peak_bytes, est.total_bytes);
        s.memory_limit = Some(Bytes(est.peak_bytes - 1));
        let e = Renderer::new(&scene)
            .settings(s)
            .render()
            .err()
            .expect("over the limit");
        let msg = e.to_string();
        assert!(
            msg.contains(&format!("1000000 photons x {size} B")),
            "{msg}"
        );
    }
}

#[test]
fn cli_photon_power_flag() {
    let parse = |extra: &[&str]| {
        let argv = ["photonmap", "render", "-o", "x.exr"]
            .iter()
            .chain(extra)
            .copied();
        Cli::try_parse_from(argv).map(|c| match c.command {
            Command::Render(a) => a.settings().f32_power(),
            Command::Merge(_) => unreachable!("`render` parses as the render command"),
        })
    };
    use clap::Parser;
    assert!(!parse(&[]).unwrap());
    assert!(!parse(&["--photon-power", "rgbe"]).unwrap());
    assert!(parse(&["--photon-power", "f32"]).unwrap());
    let e = parse(&["--photon-power", "f16"]).unwrap_err().to_string();
    assert!(e.contains("'f16'") && e.contains("rgbe, f32"), "{e}");
}
