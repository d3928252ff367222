//! The part of sphray's C API (sphray/sphray.h) this tracer uses, declared by hand: the structs
//! have the C layout (#[repr(C)]) and the functions the C calling convention.
#![allow(non_camel_case_types)]

use std::ffi::CStr;
use std::os::raw::{c_char, c_int, c_uint};

pub const SPHRAY_OK: c_int = 0;
pub const SPHRAY_NO_HIT: u32 = 0xffff_ffff;
pub const SPHRAY_THREADS_ALL: c_uint = 0xffff_ffff;

#[repr(C)]
#[derive(Clone, Copy, Default)]
pub struct sphray_ray {
    pub ox: f32,
    pub oy: f32,
    pub oz: f32,
    pub dx: f32,
    pub dy: f32,
    pub dz: f32,
    pub tmin: f32,
    pub tmax: f32,
}

#[repr(C)]
#[derive(Clone, Copy, Default)]
pub struct sphray_hit {
    pub t: f32,
    pub id: u32,
}

#[repr(C)]
#[derive(Clone, Copy, Default)]
pub struct sphray_hit_surface {
    pub px: f32,
    pub py: f32,
    pub pz: f32,
    pub nx: f32,
    pub ny: f32,
    pub nz: f32,
    pub ex: f32,
    pub ey: f32,
    pub ez: f32,
    pub front_face: i32,
}

/// A scene's options (accel, isa); this tracer passes null, the defaults.
#[repr(C)]
pub struct sphray_scene_args {
    pub struct_size: usize,
    pub accel: c_int,
    pub isa: c_int,
}

/// A query's options: masks (null: every bit) and threads.
#[repr(C)]
pub struct sphray_query_args {
    pub struct_size: usize,
    pub masks: *const u32,
    pub threads: c_uint,
}

impl Default for sphray_query_args {
    /// SPHRAY_QUERY_ARGS_INIT: struct_size set, every option its default.
    fn default() -> Self {
        sphray_query_args {
            struct_size: std::mem::size_of::<sphray_query_args>(),
            masks: std::ptr::null(),
            threads: 0,
        }
    }
}

/// Opaque: only ever behind a pointer.
#[repr(C)]
pub struct sphray_scene {
    _private: [u8; 0],
}

extern "C" {
    pub fn sphray_version() -> *const c_char;
    pub fn sphray_active_isa() -> *const c_char;
    pub fn sphray_last_error() -> *const c_char;
    pub fn sphray_scene_create(
        cx: *const f32,
        cy: *const f32,
        cz: *const f32,
        r: *const f32,
        count: usize,
        stride_bytes: usize,
        args: *const sphray_scene_args,
        out: *mut *mut sphray_scene,
    ) -> c_int;
    pub fn sphray_scene_release(scene: *mut sphray_scene) -> c_int;
    pub fn sphray_intersect(
        scene: *const sphray_scene,
        rays: *const sphray_ray,
        count: usize,
        hits: *mut sphray_hit,
        args: *const sphray_query_args,
    ) -> c_int;
    pub fn sphray_surface(
        scene: *const sphray_scene,
        rays: *const sphray_ray,
        hits: *const sphray_hit,
        count: usize,
        surfaces: *mut sphray_hit_surface,
    ) -> c_int;
}

/// A C string the library owns, as a Rust string.
pub fn text(s: *const c_char) -> String {
    unsafe { CStr::from_ptr(s) }.to_string_lossy().into_owned()
}

/// Ok, or the library's message for this thread's last failure.
pub fn check(status: c_int) -> Result<(), String> {
    if status == SPHRAY_OK {
        Ok(())
    } else {
        Err(text(unsafe { sphray_last_error() }))
    }
}
