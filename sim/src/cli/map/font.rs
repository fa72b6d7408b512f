//! The font for the picture's labels: plotters draws text only with a registered font, so the
//! binary carries one (DejaVu Sans Mono, `sim/assets/fonts/`, with its licence) and the picture has
//! labels on any machine, the same everywhere. `NUDGE_FONT` may name another TrueType file.

use std::sync::OnceLock;

use plotters::style::{FontStyle, register_font};

/// DejaVu Sans Mono 2.37, unmodified; licence in `sim/assets/fonts/LICENSE-DejaVuSansMono.txt`.
const BUNDLED: &[u8] = include_bytes!("../../../assets/fonts/DejaVuSansMono.ttf");

/// True when a font is registered as "sans-serif" (done once per process): the file `NUDGE_FONT`
/// names when it is set and loads, else the bundled font.
pub fn available() -> bool {
    static FOUND: OnceLock<bool> = OnceLock::new();
    *FOUND.get_or_init(|| {
        let from_env = std::env::var("NUDGE_FONT")
            .ok()
            .and_then(|path| std::fs::read(path).ok())
            // plotters keeps fonts for the life of the process; this happens once.
            .map(|bytes| &*Box::leak(bytes.into_boxed_slice()));
        from_env
            .into_iter()
            .chain([BUNDLED])
            .any(|bytes| register_font("sans-serif", FontStyle::Normal, bytes).is_ok())
    })
}
