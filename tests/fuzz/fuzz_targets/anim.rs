//! The animation file reader on any text: read or refused with one line, never a panic.
#![no_main]

use libfuzzer_sys::fuzz_target;
use puppet::anim::Animation;
use puppet::files::Format;

fuzz_target!(|data: &[u8]| {
    if let Ok(text) = std::str::from_utf8(data) {
        for format in [Format::Toml, Format::Json] {
            match Animation::parse(text, format).and_then(|a| a.check().map(|()| a)) {
                Ok(_) => {}
                Err(e) => assert!(!e.to_string().contains('\n'), "{e}"),
            }
        }
    }
});
