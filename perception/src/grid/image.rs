//! Snapshots of the grid as pictures, one colour per class ([`CellClass::colour`]).

use std::path::Path;

use super::class::CellClass;
use super::{GridError, ObstacleGrid};

impl ObstacleGrid {
    /// The grid as an RGBA image, one pixel per cell, map +y up: image row 0 is the grid's top row
    /// (largest y), column 0 its left column (smallest x). Colours per [`CellClass::colour`]: Unknown
    /// grey, Free white, Stationary black, Movable blue, Moving red.
    pub fn to_rgba_image(&self) -> ::image::RgbaImage {
        let (w, h) = (self.geom.width(), self.geom.height());
        let mut img = ::image::RgbaImage::new(w as u32, h as u32);
        for (row, chunk) in self.layers.class.chunks(w).enumerate() {
            let y = (h - 1 - row) as u32;
            for (x, &code) in chunk.iter().enumerate() {
                let class = CellClass::from_code(code).unwrap_or(CellClass::Unknown);
                img.put_pixel(x as u32, y, ::image::Rgba(class.colour()));
            }
        }
        img
    }

    /// Writes [`Self::to_rgba_image`] as a PNG file.
    pub fn write_png(&self, path: impl AsRef<Path>) -> Result<(), GridError> {
        self.to_rgba_image()
            .save_with_format(path, ::image::ImageFormat::Png)
            .map_err(|e| GridError::Image(e.to_string()))
    }
}
