//! What a picture is asked to be.

/// Picture settings.
#[derive(Clone, Debug)]
pub struct Settings {
    /// Raster width.
    pub width: u32,
    /// Raster height.
    pub height: u32,
    /// Cast shadows.
    pub shadows: bool,
    /// Supersampling: `samples × samples` rays per pixel (1 = none).
    pub samples: u32,
    /// Fill the region, depth and normal images.
    pub aovs: bool,
}

impl Default for Settings {
    fn default() -> Self {
        Settings {
            width: 960,
            height: 720,
            shadows: true,
            samples: 1,
            aovs: false,
        }
    }
}
