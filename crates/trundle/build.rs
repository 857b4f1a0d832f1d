//! Link the plugin library so that the dynamic loader never unmaps it (ELF `-z nodelete`).
//!
//! Rust's standard library registers a `pthread_key` destructor (for `std::thread::current`
//! and thread-local cleanup) on every host thread that calls into the plugin. If a host
//! unloads the library (`dlclose`) while such a thread is still alive — plugin scanning, a
//! removed track, a test host — that thread later runs a destructor whose code is gone and
//! crashes at exit. The CLAP host test reproduced it (SIGSEGV in `__nptl_deallocate_tsd`).
//! With `nodelete`, `dlclose` leaves the code mapped, as hosts that never unload already
//! assume; a reload reuses the same image.
fn main() {
    let os = std::env::var("CARGO_CFG_TARGET_OS").unwrap_or_default();
    let elf = matches!(
        os.as_str(),
        "linux" | "android" | "freebsd" | "netbsd" | "openbsd" | "dragonfly" | "illumos"
    );
    if elf {
        println!("cargo:rustc-cdylib-link-arg=-Wl,-z,nodelete");
    }
    println!("cargo:rerun-if-changed=build.rs");
}
