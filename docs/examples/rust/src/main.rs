//! Ray Tracing in One Weekend's first sphere, coloured by its normals, through sphray's C API:
//! the same image as `sphray render -s single -m normals --spp 1 -o image.ppm`, byte for byte.
//!
//!   PKG_CONFIG_PATH=<prefix>/lib/pkgconfig cargo build --offline --release
//!   target/release/sphray-normals image.ppm [WIDTH HEIGHT]
//!
//! The camera is the renderer's (render/src/frame/camera.cpp), operation for operation, so that
//! every ray has the same bits; the image is a PPM P3 file as the renderer writes it.
mod sphray;

use std::fs::File;
use std::io::{BufWriter, Write};
use std::ops::{Add, Div, Mul, Sub};
use std::ptr;

use sphray::*;

#[derive(Clone, Copy)]
struct Vec3 {
    x: f32,
    y: f32,
    z: f32,
}

const fn vec3(x: f32, y: f32, z: f32) -> Vec3 {
    Vec3 { x, y, z }
}

impl Add for Vec3 {
    type Output = Vec3;
    fn add(self, b: Vec3) -> Vec3 {
        vec3(self.x + b.x, self.y + b.y, self.z + b.z)
    }
}
impl Sub for Vec3 {
    type Output = Vec3;
    fn sub(self, b: Vec3) -> Vec3 {
        vec3(self.x - b.x, self.y - b.y, self.z - b.z)
    }
}
impl Mul<Vec3> for f32 {
    type Output = Vec3;
    fn mul(self, v: Vec3) -> Vec3 {
        vec3(self * v.x, self * v.y, self * v.z)
    }
}
impl Div<f32> for Vec3 {
    type Output = Vec3;
    fn div(self, s: f32) -> Vec3 {
        vec3(self.x / s, self.y / s, self.z / s)
    }
}

fn dot(a: Vec3, b: Vec3) -> f32 {
    a.x * b.x + a.y * b.y + a.z * b.z
}
fn cross(a: Vec3, b: Vec3) -> Vec3 {
    vec3(
        a.y * b.z - a.z * b.y,
        a.z * b.x - a.x * b.z,
        a.x * b.y - a.y * b.x,
    )
}
fn normalize(v: Vec3) -> Vec3 {
    v / dot(v, v).sqrt()
}

/// The book's pinhole camera: rays from lookfrom through a viewport at distance 1.
struct Camera {
    origin: Vec3,
    upper_left: Vec3,
    pixel_du: Vec3,
    pixel_dv: Vec3,
}

impl Camera {
    fn new(lookfrom: Vec3, lookat: Vec3, vup: Vec3, vfov: f32, width: u32, height: u32) -> Camera {
        let theta = vfov * std::f32::consts::PI / 180.0;
        let viewport_height = 2.0 * (theta / 2.0).tan();
        let viewport_width = viewport_height * width as f32 / height as f32;
        let w = normalize(lookfrom - lookat);
        let u = normalize(cross(vup, w));
        let v = cross(w, u);
        let viewport_u = viewport_width * u;
        let viewport_v = viewport_height * (-1.0 * v); // rows run downwards
        Camera {
            origin: lookfrom,
            pixel_du: viewport_u / width as f32,
            pixel_dv: viewport_v / height as f32,
            upper_left: -1.0 * w - viewport_u / 2.0 - viewport_v / 2.0,
        }
    }

    /// The ray through the centre of pixel (x, y); the direction is not normalised.
    fn ray(&self, x: u32, y: u32) -> sphray_ray {
        let (px, py) = (x as f32 + 0.5, y as f32 + 0.5);
        let d = self.upper_left + px * self.pixel_du + py * self.pixel_dv;
        let o = self.origin;
        sphray_ray {
            ox: o.x,
            oy: o.y,
            oz: o.z,
            dx: d.x,
            dy: d.y,
            dz: d.z,
            tmin: 0.0,
            tmax: f32::INFINITY,
        }
    }
}

/// The book's sky: white to blue by the direction's height.
fn sky(r: &sphray_ray) -> Vec3 {
    let a = 0.5 * (normalize(vec3(r.dx, r.dy, r.dz)).y + 1.0);
    (1.0 - a) * vec3(1.0, 1.0, 1.0) + a * vec3(0.5, 0.7, 1.0)
}

fn to_byte(c: f32) -> u8 {
    let clamped = if c > 0.0 { c.min(1.0) } else { 0.0 };
    (255.999 * clamped) as u8
}

fn render(path: &str, width: u32, height: u32) -> Result<(), String> {
    let (cx, cy, cz, r) = (0.0f32, 0.0f32, -1.0f32, 0.5f32);
    let mut scene: *mut sphray_scene = ptr::null_mut();
    check(unsafe { sphray_scene_create(&cx, &cy, &cz, &r, 1, 0, ptr::null(), &mut scene) })?;

    let camera = Camera::new(
        vec3(0.0, 0.0, 0.0),
        vec3(0.0, 0.0, -1.0),
        vec3(0.0, 1.0, 0.0),
        90.0,
        width,
        height,
    );
    let rays: Vec<sphray_ray> = (0..height)
        .flat_map(|y| (0..width).map(move |x| (x, y)))
        .map(|(x, y)| camera.ray(x, y))
        .collect();
    let n = rays.len();
    let mut hits = vec![sphray_hit::default(); n];
    let mut surfaces = vec![sphray_hit_surface::default(); n];
    // Every core; the hits are the same on any number of threads.
    let args = sphray_query_args {
        threads: SPHRAY_THREADS_ALL,
        ..Default::default()
    };
    let traced =
        check(unsafe { sphray_intersect(scene, rays.as_ptr(), n, hits.as_mut_ptr(), &args) })
            .and_then(|_| {
                check(unsafe {
                    sphray_surface(
                        scene,
                        rays.as_ptr(),
                        hits.as_ptr(),
                        n,
                        surfaces.as_mut_ptr(),
                    )
                })
            });
    unsafe { sphray_scene_release(scene) };
    traced?;

    let file = File::create(path).map_err(|e| format!("{}: {}", path, e))?;
    let mut out = BufWriter::new(file);
    let mut write = || -> std::io::Result<()> {
        write!(out, "P3\n{} {}\n255\n", width, height)?;
        for i in 0..n {
            let c = if hits[i].id == SPHRAY_NO_HIT {
                sky(&rays[i])
            } else {
                let s = &surfaces[i]; // the normal, from [-1, 1] to [0, 1]
                0.5 * (vec3(s.nx, s.ny, s.nz) + vec3(1.0, 1.0, 1.0))
            };
            writeln!(out, "{} {} {}", to_byte(c.x), to_byte(c.y), to_byte(c.z))?;
        }
        out.flush()
    };
    write().map_err(|e| format!("{}: {}", path, e))?;
    println!(
        "{}: {}x{}, sphray {} on {}",
        path,
        width,
        height,
        text(unsafe { sphray_version() }),
        text(unsafe { sphray_active_isa() })
    );
    Ok(())
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let size = |s: &String| s.parse::<u32>().ok().filter(|v| (1..=16384).contains(v));
    let (width, height) = match args.len() {
        2 => (Some(400), Some(225)),
        4 => (size(&args[2]), size(&args[3])),
        _ => (None, None),
    };
    let (width, height) = match (width, height) {
        (Some(w), Some(h)) => (w, h),
        _ => {
            eprintln!(
                "usage: {} OUTPUT.ppm [WIDTH HEIGHT] (1 to 16384 pixels a side)",
                args[0]
            );
            std::process::exit(2);
        }
    };
    if let Err(message) = render(&args[1], width, height) {
        eprintln!("{}", message);
        std::process::exit(1);
    }
}
