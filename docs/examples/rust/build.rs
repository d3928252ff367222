// Links libsphray.so: its directory comes from pkg-config (PKG_CONFIG_PATH=prefix/lib/pkgconfig
// for an install outside the system's paths), and is recorded as the binary's run path, so the
// tracer runs without LD_LIBRARY_PATH.
use std::process::Command;

fn main() {
    println!("cargo:rerun-if-env-changed=PKG_CONFIG_PATH");
    let output = Command::new("pkg-config")
        .args(["--libs-only-L", "sphray"])
        .output()
        .expect("pkg-config is needed to find sphray");
    if !output.status.success() {
        panic!(
            "pkg-config cannot find sphray (set PKG_CONFIG_PATH to <prefix>/lib/pkgconfig): {}",
            String::from_utf8_lossy(&output.stderr)
        );
    }
    for flag in String::from_utf8_lossy(&output.stdout).split_whitespace() {
        if let Some(dir) = flag.strip_prefix("-L") {
            println!("cargo:rustc-link-search=native={}", dir);
            println!("cargo:rustc-link-arg=-Wl,-rpath,{}", dir);
        }
    }
    println!("cargo:rustc-link-lib=dylib=sphray");
}
