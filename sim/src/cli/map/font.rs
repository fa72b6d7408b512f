//! A font for the picture's labels, found on the machine: plotters draws text only with a
//! registered font. Without one the picture is drawn without labels.

use std::sync::OnceLock;

use plotters::style::{FontStyle, register_font};

/// Where common systems keep a sans-serif TrueType font; `NUDGE_FONT` comes first when set.
const CANDIDATES: [&str; 5] = [
    "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf",
    "/usr/share/fonts/dejavu/DejaVuSans.ttf",
    "/usr/share/fonts/TTF/DejaVuSans.ttf",
    "/System/Library/Fonts/Supplemental/Arial.ttf",
    "C:\\Windows\\Fonts\\arial.ttf",
];

/// True when a font is registered as "sans-serif" (looked for once per process).
pub fn available() -> bool {
    static FOUND: OnceLock<bool> = OnceLock::new();
    *FOUND.get_or_init(|| {
        let from_env = std::env::var("NUDGE_FONT").ok();
        from_env
            .iter()
            .map(String::as_str)
            .chain(CANDIDATES)
            .any(|path| {
                let Ok(bytes) = std::fs::read(path) else {
                    return false;
                };
                // plotters keeps fonts for the life of the process; this happens once.
                let bytes: &'static [u8] = Box::leak(bytes.into_boxed_slice());
                register_font("sans-serif", FontStyle::Normal, bytes).is_ok()
            })
    })
}
