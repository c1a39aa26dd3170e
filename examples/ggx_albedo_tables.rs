//! Writes `src/materials/ggx_albedo.bin` and `src/materials/ggx_glass_albedo.bin`, the GGX
//! albedo tables the renderer embeds (`materials::layer::tables`,
//! `materials::glass_albedo::tables`): `cargo run --release --example ggx_albedo_tables`.

fn write(name: &str, data: &[f32]) {
    let bytes: Vec<u8> = data.iter().flat_map(|v| v.to_le_bytes()).collect();
    let path = format!("{}/src/materials/{name}", env!("CARGO_MANIFEST_DIR"));
    std::fs::write(&path, &bytes).expect("writes the tables");
    eprintln!("{} floats to {path}", data.len());
}

fn main() {
    let t = std::time::Instant::now();
    write("ggx_albedo.bin", &photonmap::materials::layer::tables());
    write(
        "ggx_glass_albedo.bin",
        &photonmap::materials::glass_albedo::tables(),
    );
    eprintln!("in {:.1} s", t.elapsed().as_secs_f64());
}
