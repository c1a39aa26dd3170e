//! Writes `src/materials/ggx_albedo.bin`, the GGX albedo tables the renderer embeds
//! (`materials::layer::tables`): `cargo run --release --example ggx_albedo_tables`.

fn main() {
    let t = std::time::Instant::now();
    let data = photonmap::materials::layer::tables();
    let bytes: Vec<u8> = data.iter().flat_map(|v| v.to_le_bytes()).collect();
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/src/materials/ggx_albedo.bin");
    std::fs::write(path, &bytes).expect("writes the tables");
    eprintln!(
        "{} floats to {path} in {:.1} s",
        data.len(),
        t.elapsed().as_secs_f64()
    );
}
