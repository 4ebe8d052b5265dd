//! The rig file reader on any text: read or refused with one line, never a panic.
#![no_main]

use libfuzzer_sys::fuzz_target;
use puppet::files::Format;

fuzz_target!(|data: &[u8]| {
    if let Ok(text) = std::str::from_utf8(data) {
        for format in [Format::Toml, Format::Json] {
            if let Err(e) = puppet::RigFile::parse(text, format, std::path::Path::new(".")) {
                assert!(!e.to_string().contains('\n'), "{e}");
            }
        }
    }
});
