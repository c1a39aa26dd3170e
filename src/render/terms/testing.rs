//! Small scenes for the terms' tests: a floor at z = 0 seen from above, built from IR JSON.

use crate::geometry::{Ray, SurfaceInteraction};
use crate::materials::bsdf::Bsdf;
use crate::scene::{Scene, SceneDesc, SceneHit};
use glam::Vec3;

/// The floor mesh, 20 × 20 around the origin in the plane z = 0, with material `material`.
pub fn floor(material: u32) -> serde_json::Value {
    serde_json::json!({
        "name": "floor", "material": material,
        "positions": [[-10, -10, 0], [10, -10, 0], [10, 10, 0], [-10, 10, 0]],
        "indices": [[0, 1, 2], [0, 2, 3]],
    })
}

/// A scene of these parts (`materials`, `meshes`, `lights`, and anything else the IR takes)
/// under a camera above the origin looking down.
pub fn scene(parts: serde_json::Value) -> Scene {
    let mut desc = serde_json::json!({
        "camera": {"transform": [[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 3], [0, 0, 0, 1]],
                   "fov": 0.7},
        "film": {"width": 4, "height": 4},
    });
    for (k, v) in parts.as_object().expect("an object of scene parts") {
        desc[k] = v.clone();
    }
    let desc: SceneDesc = serde_json::from_value(desc).expect("a valid test scene");
    Scene::build(&desc).expect("the test scene builds")
}

/// The first surface straight below (x, 0, 2), with its shading BSDF.
pub fn hit_below(scene: &Scene, x: f32) -> (SurfaceInteraction, Bsdf) {
    let ray = Ray {
        o: Vec3::new(x, 0.0, 2.0),
        d: Vec3::new(0.0, 0.0, -1.0),
        t_max: f32::INFINITY,
    };
    let SceneHit::Surface(mut si) = scene.intersect(&ray) else {
        panic!("the ray from (x, 0, 2) downwards hits the floor");
    };
    let mat = &scene.materials[si.material as usize];
    let bsdf = scene.shading_bsdf(mat, &mut si);
    (si, bsdf)
}
