//! Compiles the C++ shim over OMPL's Dubins state space and links OMPL
//! (Debian `libompl-dev`; its flags from `pkg-config ompl`).

use std::process::Command;

fn main() {
    println!("cargo:rerun-if-changed=cpp/dubins.cpp");
    let flags = match Command::new("pkg-config")
        .args(["--cflags", "ompl"])
        .output()
    {
        Ok(out) if out.status.success() => String::from_utf8_lossy(&out.stdout).into_owned(),
        _ => {
            println!(
                "cargo:warning=pkg-config does not know OMPL: install Debian's libompl-dev \
                 (apt-get install libompl-dev)"
            );
            std::process::exit(1);
        }
    };
    let mut build = cc::Build::new();
    build.cpp(true).file("cpp/dubins.cpp").warnings(true);
    for flag in flags.split_whitespace() {
        if let Some(dir) = flag.strip_prefix("-I") {
            build.include(dir);
        } else if flag.starts_with("-std=") {
            // OMPL 1.5 asks for C++14; its headers build as C++17 too.
            build.flag("-std=c++17");
        }
    }
    build.compile("fieldguide_ompl_shim");
    println!("cargo:rustc-link-lib=ompl");
}
