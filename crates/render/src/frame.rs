/// A rendered picture: linear RGB, coverage (alpha) and, optionally, the
/// auxiliary images (region id, depth, normal) of the pixel centres.
#[derive(Clone, Debug, PartialEq)]
pub struct Frame {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// Linear intensity per channel, row-major from the top-left.
    pub rgb: Vec<[f32; 3]>,
    /// Fraction of the pixel's samples that hit geometry.
    pub alpha: Vec<f32>,
    /// Region index + 1 of the pixel centre (0: background). Empty unless
    /// auxiliary images were requested.
    pub region: Vec<u32>,
    /// Distance from the eye (infinite for background).
    pub depth: Vec<f32>,
    /// World-space unit normal (zero for background).
    pub normal: Vec<[f32; 3]>,
}

impl Frame {
    /// A black frame.
    pub fn new(width: u32, height: u32, aovs: bool) -> Frame {
        let n = width as usize * height as usize;
        let a = if aovs { n } else { 0 };
        Frame {
            width,
            height,
            rgb: vec![[0.0; 3]; n],
            alpha: vec![0.0; n],
            region: vec![0; a],
            depth: vec![f32::INFINITY; a],
            normal: vec![[0.0; 3]; a],
        }
    }

    /// Grey level (mean of the channels) of pixel `(x, y)`.
    pub fn grey(&self, x: u32, y: u32) -> f32 {
        let c = self.rgb[(y * self.width + x) as usize];
        (c[0] + c[1] + c[2]) / 3.0
    }

    /// A small ASCII rendering (`#` geometry, `.` background), one
    /// character per pixel; used for readable snapshot tests.
    pub fn ascii(&self) -> String {
        let mut s = String::new();
        for y in 0..self.height {
            for x in 0..self.width {
                s.push(if self.alpha[(y * self.width + x) as usize] > 0.5 {
                    '#'
                } else {
                    '.'
                });
            }
            s.push('\n');
        }
        s
    }
}
