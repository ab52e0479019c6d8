//! Build script: puts the target's memory map on the linker's search path
//! as memory.x (cortex-m-rt's and riscv-rt's link.x need it) and computes the scene's quadrature reference on the
//! host in f64, so that the firmware embeds it as a constant and needs no
//! f64 code for it.

use glam::DVec3;
use omnee_core::medium::Homogeneous;
use omnee_core::phase::HenyeyGreenstein;
use omnee_core::reference::PointToPoint;
use omnee_core::sampling::Connection;
use std::{env, fs, path::PathBuf};

#[allow(dead_code)]
mod scene {
    include!("src/scene.rs");
}
use scene::*;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let out = PathBuf::from(env::var_os("OUT_DIR").ok_or("OUT_DIR not set")?);
    // cortex-m-rt's link.x includes memory.x; riscv-rt's takes
    // memory-riscv.x from the command line (.cargo/config.toml).
    for memory in ["memory.x", "memory-riscv.x"] {
        fs::copy(memory, out.join(memory))?;
    }
    println!("cargo:rustc-link-search={}", out.display());
    println!("cargo:rerun-if-changed=memory.x");
    println!("cargo:rerun-if-changed=memory-riscv.x");
    println!("cargo:rerun-if-changed=src/scene.rs");

    // The f32 scene's numbers, widened exactly.
    let v = |p: [f32; 3]| DVec3::new(p[0].into(), p[1].into(), p[2].into());
    let connection = Connection::<f64>::new(v(X0), v(X2), THETA_MAX.into())?;
    let medium = Homogeneous::<f64>::new(SIGMA_S.into(), SIGMA_A.into())?;
    let problem = PointToPoint::new(connection, medium, None)?;
    let reference = problem.integral(&HenyeyGreenstein::<f64>::new(G.into())?);
    fs::write(
        out.join("reference.rs"),
        format!(
            "/// The scene's integral by the core's quadrature on the host, f64 bits ({reference:e}).\n\
             pub const REFERENCE_BITS: u64 = {:#018x};\n",
            reference.to_bits()
        ),
    )?;
    Ok(())
}
