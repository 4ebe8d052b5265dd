//! The obj reader on any bytes: read or refused with one line, never a panic.
#![no_main]

use libfuzzer_sys::fuzz_target;
use puppet::mesh::{parse, Format, LoadOptions};

fuzz_target!(|data: &[u8]| {
    if let Err(e) = parse(
        data,
        Format::Obj,
        &LoadOptions::default(),
        puppet::progress::silent(),
    ) {
        assert!(!e.to_string().contains('\n'), "{e}");
    }
});
