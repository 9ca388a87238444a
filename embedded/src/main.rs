//! The firmware: the Pierre 2022 pipeline on the example's field, one line
//! per tick over semihosting, then the footprint, then exit with success
//! (failure on any error or panic).
//!
//! Built for the host (`--target` of the host), the same program prints the
//! same tick lines to stdout: `.ci/run` compares the two. Lines starting
//! with `#` are the footprint, which differs between targets, and are not
//! compared.
#![cfg_attr(target_os = "none", no_std, no_main)]

#[cfg(not(feature = "compact"))]
type Chosen = fieldguide_embedded::FullDetector;
#[cfg(feature = "compact")]
type Chosen = fieldguide_embedded::CompactDetector;

/// The capacities' name, for the footprint lines.
const CAPACITIES: &str = if cfg!(feature = "compact") {
    "compact (384, 64, 192, 25)"
} else {
    "default (512, 64, 512, 32)"
};

#[cfg(target_os = "none")]
mod firmware {
    use cortex_m_rt::entry;
    use cortex_m_semihosting::{debug, hprintln};
    use fieldguide_embedded::{field_size, path_size, pipeline_size, run, PATH_CAPACITY};

    use super::{Chosen, CAPACITIES};

    extern "C" {
        /// The top of the stack (cortex-m-rt's linker script).
        static _stack_start: u32;
        /// The lowest address the stack may grow to: the end of the
        /// statics (cortex-m-rt's linker script).
        static _stack_end: u32;
    }

    /// Bytes of stack used since reset: cortex-m-rt's `paint-stack` filled
    /// `_stack_end.._stack_start` with `STACK_PAINT_VALUE` before `main`;
    /// the lowest word no longer holding it is the deepest the stack went.
    fn stack_used() -> usize {
        let bottom = core::ptr::addr_of!(_stack_end);
        let top = core::ptr::addr_of!(_stack_start);
        let mut word = bottom;
        while word < top {
            // SAFETY: `word` lies in `_stack_end.._stack_start`, RAM that the
            // linker script reserves for the stack, and is 4-aligned (the
            // script asserts `_stack_end % 4 == 0` and we step by words). A
            // volatile read of a `u32` there is always defined; words below
            // the deepest frame belong to no live object.
            let value = unsafe { core::ptr::read_volatile(word) };
            if value != cortex_m_rt::STACK_PAINT_VALUE {
                break;
            }
            word = word.wrapping_add(1);
        }
        (top as usize).saturating_sub(word as usize)
    }

    #[entry]
    fn main() -> ! {
        let result = run::<Chosen>(|line| hprintln!("{}", line));
        let used = stack_used();
        hprintln!(
            "# capacities {}, path {} vertices",
            CAPACITIES,
            PATH_CAPACITY
        );
        hprintln!(
            "# size_of: pipeline {} B, path {} B, field {} B",
            pipeline_size::<Chosen>(),
            path_size(),
            field_size()
        );
        hprintln!("# stack used: {} B", used);
        match result {
            Ok(()) => debug::exit(debug::EXIT_SUCCESS),
            Err(e) => {
                hprintln!("# error: {}", e);
                debug::exit(debug::EXIT_FAILURE);
            }
        }
        loop {
            cortex_m::asm::nop();
        }
    }

    #[panic_handler]
    fn panic(info: &core::panic::PanicInfo<'_>) -> ! {
        hprintln!("# panic: {}", info);
        debug::exit(debug::EXIT_FAILURE);
        loop {
            cortex_m::asm::nop();
        }
    }
}

#[cfg(not(target_os = "none"))]
fn main() -> std::process::ExitCode {
    use fieldguide_embedded::{field_size, path_size, pipeline_size, run, PATH_CAPACITY};

    let result = run::<Chosen>(|line| println!("{line}"));
    println!("# capacities {CAPACITIES}, path {PATH_CAPACITY} vertices (host)");
    println!(
        "# size_of: pipeline {} B, path {} B, field {} B (host)",
        pipeline_size::<Chosen>(),
        path_size(),
        field_size()
    );
    match result {
        Ok(()) => std::process::ExitCode::SUCCESS,
        Err(e) => {
            println!("# error: {e}");
            std::process::ExitCode::FAILURE
        }
    }
}
