//! The few Embree 3 calls the BVH bench needs, declared by hand (`libembree3`, Debian's
//! `libembree-dev`): a scene of triangle meshes, committed, and single-ray closest hits.
//! Only built with the `embree-bench` feature; the renderer never links Embree.
//!
//! The structures follow `embree3/rtcore_ray.h` and `rtcore_common.h` for a build with
//! `RTC_MAX_INSTANCE_LEVEL_COUNT == 1` and `RTC_MIN_WIDTH == 0` (Debian's 3.13.5).

use photonmap::geometry::{MeshGeom, Ray};
use std::ffi::{c_char, c_void, CString};
use std::ptr;

type RTCDevice = *mut c_void;
type RTCScene = *mut c_void;
type RTCGeometry = *mut c_void;

const RTC_GEOMETRY_TYPE_TRIANGLE: u32 = 0;
const RTC_BUFFER_TYPE_INDEX: u32 = 0;
const RTC_BUFFER_TYPE_VERTEX: u32 = 1;
const RTC_FORMAT_UINT3: u32 = 0x5003;
const RTC_FORMAT_FLOAT3: u32 = 0x9003;
const RTC_INVALID_GEOMETRY_ID: u32 = u32::MAX;
const RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT: u32 = 0;

#[repr(C)]
struct RTCIntersectContext {
    flags: u32,
    filter: *const c_void,
    inst_id: [u32; 1],
}

#[repr(C, align(16))]
struct RTCRay {
    org: [f32; 3],
    tnear: f32,
    dir: [f32; 3],
    time: f32,
    tfar: f32,
    mask: u32,
    id: u32,
    flags: u32,
}

#[repr(C, align(16))]
struct RTCHit {
    ng: [f32; 3],
    u: f32,
    v: f32,
    prim_id: u32,
    geom_id: u32,
    inst_id: [u32; 1],
}

#[repr(C)]
struct RTCRayHit {
    ray: RTCRay,
    hit: RTCHit,
}

#[link(name = "embree3")]
extern "C" {
    fn rtcNewDevice(config: *const c_char) -> RTCDevice;
    fn rtcReleaseDevice(device: RTCDevice);
    fn rtcGetDeviceError(device: RTCDevice) -> u32;
    fn rtcNewScene(device: RTCDevice) -> RTCScene;
    fn rtcReleaseScene(scene: RTCScene);
    fn rtcNewGeometry(device: RTCDevice, kind: u32) -> RTCGeometry;
    fn rtcReleaseGeometry(geometry: RTCGeometry);
    fn rtcSetNewGeometryBuffer(
        geometry: RTCGeometry,
        kind: u32,
        slot: u32,
        format: u32,
        byte_stride: usize,
        item_count: usize,
    ) -> *mut c_void;
    fn rtcCommitGeometry(geometry: RTCGeometry);
    fn rtcAttachGeometry(scene: RTCScene, geometry: RTCGeometry) -> u32;
    fn rtcCommitScene(scene: RTCScene);
    fn rtcIntersect1(scene: RTCScene, context: *mut RTCIntersectContext, rayhit: *mut RTCRayHit);
}

/// An Embree device and a committed scene of triangle meshes (default build quality and
/// scene flags, as Embree's tutorials use them).
pub struct EmbreeScene {
    device: RTCDevice,
    scene: RTCScene,
}

impl EmbreeScene {
    /// Builds the scene from `meshes`, one triangle geometry each, with Embree's own threads
    /// (`config` as `rtcNewDevice` takes it, e.g. `"threads=2"`).
    pub fn new(meshes: &[MeshGeom], config: &str) -> EmbreeScene {
        let config = CString::new(config).expect("no NUL in the config");
        // SAFETY: plain Embree API use: buffers are filled within their declared sizes
        // before the geometry is committed, and every handle is checked or released.
        unsafe {
            let device = rtcNewDevice(config.as_ptr());
            assert!(!device.is_null(), "rtcNewDevice failed");
            let scene = rtcNewScene(device);
            for m in meshes {
                let geom = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
                let v = rtcSetNewGeometryBuffer(
                    geom,
                    RTC_BUFFER_TYPE_VERTEX,
                    0,
                    RTC_FORMAT_FLOAT3,
                    12,
                    m.positions.len(),
                ) as *mut [f32; 3];
                assert!(!v.is_null(), "vertex buffer");
                for (i, p) in m.positions.iter().enumerate() {
                    v.add(i).write(p.to_array());
                }
                let ix = rtcSetNewGeometryBuffer(
                    geom,
                    RTC_BUFFER_TYPE_INDEX,
                    0,
                    RTC_FORMAT_UINT3,
                    12,
                    m.indices.len(),
                ) as *mut [u32; 3];
                assert!(!ix.is_null(), "index buffer");
                ptr::copy_nonoverlapping(m.indices.as_ptr(), ix, m.indices.len());
                rtcCommitGeometry(geom);
                rtcAttachGeometry(scene, geom);
                rtcReleaseGeometry(geom);
            }
            rtcCommitScene(scene);
            assert_eq!(rtcGetDeviceError(device), 0, "Embree error");
            EmbreeScene { device, scene }
        }
    }

    /// Distance along `ray.d` (in units of its length) to the closest hit, if any.
    #[inline]
    pub fn closest(&self, ray: &Ray) -> Option<f32> {
        let mut ctx = RTCIntersectContext {
            flags: RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT,
            filter: ptr::null(),
            inst_id: [RTC_INVALID_GEOMETRY_ID],
        };
        let mut rh = RTCRayHit {
            ray: RTCRay {
                org: ray.o.to_array(),
                tnear: 0.0,
                dir: ray.d.to_array(),
                time: 0.0,
                tfar: ray.t_max,
                mask: u32::MAX,
                id: 0,
                flags: 0,
            },
            hit: RTCHit {
                ng: [0.0; 3],
                u: 0.0,
                v: 0.0,
                prim_id: RTC_INVALID_GEOMETRY_ID,
                geom_id: RTC_INVALID_GEOMETRY_ID,
                inst_id: [RTC_INVALID_GEOMETRY_ID],
            },
        };
        // SAFETY: the scene is committed and the structures match Embree's layout.
        unsafe { rtcIntersect1(self.scene, &mut ctx, &mut rh) };
        (rh.hit.geom_id != RTC_INVALID_GEOMETRY_ID).then_some(rh.ray.tfar)
    }
}

impl Drop for EmbreeScene {
    fn drop(&mut self) {
        // SAFETY: both handles were created by `new` and are released once.
        unsafe {
            rtcReleaseScene(self.scene);
            rtcReleaseDevice(self.device);
        }
    }
}
