//! Rebuilds the library when a bundled vehicle or scenario changes (`bundled.rs` embeds them
//! with `include_dir!`, which cargo does not track by itself on stable Rust).

fn main() {
    println!("cargo:rerun-if-changed=../../vehicles");
    println!("cargo:rerun-if-changed=../../scenarios");
}
