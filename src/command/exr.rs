//! Multilayer float32 EXR, per the contract: the beauty in `R,G,B,A` (the default layer, so any
//! viewer shows it), each term in `<term>.R/G/B`, the AOVs beside the terms as
//! `aov::AovRequest::aovs` lists them (`error.R/G/B`, `albedo.R/G/B`, `normal.X/Y/Z`,
//! `lightgroup.<name>.R/G/B`, `CryptoObject00.R/G/B/A`, ...), and metadata as string
//! attributes: the renderer's under `photonmap/`, Cryptomatte's under `cryptomatte/<key>/`.

use crate::error::{Error, Result};
use crate::render::aov::Term;
use crate::render::film::{Film, Image};
use exr::prelude::*;
use std::collections::BTreeMap;
use std::path::Path;

fn channel(name: String, img: &Image, c: usize) -> AnyChannel<FlatSamples> {
    AnyChannel::new(
        name.as_str(),
        FlatSamples::F32(img.data.iter().map(|p| p[c]).collect()),
    )
}

/// Name of the layer holding the `error` AOV (the estimated standard error of the beauty).
pub const ERROR_AOV: &str = crate::render::aov::ERROR_AOV;

/// Writes the beauty, every term and every AOV beside them. `metadata` becomes string
/// attributes of the header, each under `photonmap/`; the film's Cryptomatte manifests
/// become the specification's `cryptomatte/<key>/...` attributes.
pub fn write_multilayer(
    path: impl AsRef<Path>,
    film: &Film,
    metadata: &BTreeMap<String, String>,
) -> Result<()> {
    let path = path.as_ref();
    multilayer_image(film, metadata)
        .write()
        .to_file(path)
        .map_err(|e| Error::io(path, e))
}

/// Seconds that writing `film` as a multilayer EXR should take on this machine: a strip of
/// its rows (at least 16 rows and 16384 pixels; compression costs depend on the data) is
/// encoded in memory after a warm-up, and the time scaled to the whole film, plus 10%. A
/// command under a time budget leaves this much for its output.
pub fn estimate_write_seconds(film: &Film) -> f64 {
    let (w, h) = (film.width.max(1), film.height);
    if h == 0 {
        return 0.0;
    }
    let rows = (16384usize.div_ceil(w)).max(16).min(h);
    let strip = |rows: usize| {
        let mut s = Film::new(w, rows);
        for (dst, src) in s.terms.iter_mut().zip(&film.terms) {
            dst.data.copy_from_slice(&src.data[..w * rows]);
        }
        s.error.data.copy_from_slice(&film.error.data[..w * rows]);
        s.alpha.copy_from_slice(&film.alpha[..w * rows]);
        s.aovs = film
            .aovs
            .iter()
            .map(|a| {
                let n = a.spec.channels().len();
                crate::render::film::AovImage {
                    spec: a.spec.clone(),
                    data: a.data[..w * rows * n].to_vec(),
                }
            })
            .collect();
        s
    };
    let encode = |f: &Film| {
        let t0 = std::time::Instant::now();
        let mut buf = std::io::Cursor::new(Vec::new());
        let ok = multilayer_image(f, &BTreeMap::new())
            .write()
            .to_buffered(&mut buf)
            .is_ok();
        if ok {
            t0.elapsed().as_secs_f64()
        } else {
            0.0
        }
    };
    encode(&strip(1.min(h)));
    let secs = encode(&strip(rows));
    1.1 * secs * h as f64 / rows as f64
}

fn multilayer_image(
    film: &Film,
    metadata: &BTreeMap<String, String>,
) -> exr::prelude::Image<Layer<AnyChannels<FlatSamples>>> {
    let combined = film.combined();
    let mut channels: Vec<AnyChannel<FlatSamples>> = Vec::new();
    for (c, n) in ["R", "G", "B"].iter().enumerate() {
        channels.push(channel((*n).to_string(), &combined, c));
    }
    channels.push(AnyChannel::new("A", FlatSamples::F32(film.alpha.clone())));
    for t in Term::ALL {
        for (c, n) in ["R", "G", "B"].iter().enumerate() {
            channels.push(channel(format!("{}.{n}", t.name()), film.term(t), c));
        }
    }
    for (spec, data) in film.extra_images() {
        let names = spec.channels();
        for (c, n) in names.iter().enumerate() {
            let v: Vec<f32> = data.iter().skip(c).step_by(names.len()).copied().collect();
            channels.push(AnyChannel::new(
                format!("{}.{n}", spec.name).as_str(),
                FlatSamples::F32(v),
            ));
        }
    }
    let mut attrs = LayerAttributes::default();
    let text = |k: &str, v: &str| (Text::from(k), AttributeValue::Text(Text::from(v)));
    for (k, v) in metadata {
        let (k, v) = text(&format!("photonmap/{k}"), v);
        attrs.other.insert(k, v);
    }
    for (k, v) in crate::render::compositing::cryptomatte_header(&film.cryptomatte, "") {
        let (k, v) = text(&k, &v);
        attrs.other.insert(k, v);
    }
    let layer = Layer::new(
        (film.width, film.height),
        attrs,
        Encoding::SMALL_LOSSLESS,
        AnyChannels::sort(channels.into()),
    );
    exr::prelude::Image::from_layer(layer)
}

/// Reads every RGB (or XYZ) group of a single-part EXR: `""` for `R,G,B`, and `"direct"` for
/// `direct.R/G/B`, and so on. Also returns the string attributes.
pub fn read_rgb_layers(
    path: impl AsRef<Path>,
) -> Result<(BTreeMap<String, Image>, BTreeMap<String, String>)> {
    let path = path.as_ref();
    let img = read()
        .no_deep_data()
        .largest_resolution_level()
        .all_channels()
        .all_layers()
        .all_attributes()
        .from_file(path)
        .map_err(|e| Error::io(path, e))?;
    let mut out = BTreeMap::new();
    let mut meta = BTreeMap::new();
    for layer in &img.layer_data {
        let (w, h) = (layer.size.width(), layer.size.height());
        let layer_prefix = layer
            .attributes
            .layer_name
            .as_ref()
            .map(|t| format!("{t}."))
            .unwrap_or_default();
        for (k, v) in &layer.attributes.other {
            if let AttributeValue::Text(t) = v {
                meta.insert(k.to_string(), t.to_string());
            }
        }
        for ch in &layer.channel_data.list {
            let full = format!("{layer_prefix}{}", ch.name);
            let (group, comp) = match full.rsplit_once('.') {
                Some((g, c)) => (g.to_string(), c.to_string()),
                None => (String::new(), full.clone()),
            };
            let c = match comp.as_str() {
                "R" | "r" | "X" => 0,
                "G" | "g" | "Y" => 1,
                "B" | "b" | "Z" => 2,
                _ => continue,
            };
            let entry = out.entry(group).or_insert_with(|| Image::new(w, h));
            for (i, v) in ch.sample_data.values_as_f32().enumerate() {
                entry.data[i][c] = v;
            }
        }
    }
    Ok((out, meta))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::render::film::TermRadiance;
    use glam::Vec3;

    #[test]
    fn writes_terms_and_beauty_as_float32() {
        let mut film = Film::new(3, 2);
        let mut px = TermRadiance::default();
        px.add(Term::Caustic, Vec3::new(1e6, 2.0, 3.0));
        px.add(Term::Direct, Vec3::new(0.25, 0.5, 0.125));
        film.set_pixel(2, 1, &px);
        let dir = std::env::temp_dir().join(format!("pm_exr_{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("t.exr");
        let mut meta = BTreeMap::new();
        meta.insert("seed".to_string(), "7".to_string());
        write_multilayer(&path, &film, &meta).unwrap();
        let (layers, m) = read_rgb_layers(&path).unwrap();
        assert_eq!(m.get("photonmap/seed").map(String::as_str), Some("7"));
        assert_eq!(layers[""].get(2, 1), Vec3::new(1e6 + 0.25, 2.5, 3.125));
        assert_eq!(layers["caustic"].get(2, 1), Vec3::new(1e6, 2.0, 3.0));
        for t in Term::ALL {
            assert!(layers.contains_key(t.name()));
        }
        assert_eq!(layers[""].get(0, 0), Vec3::ZERO);
        std::fs::remove_dir_all(dir).ok();
    }
}
