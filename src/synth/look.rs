//! Looks: the colours of each style and its lighting, and the colour arithmetic and
//! drawing coordinates shared by the scene, the moving parts and the hand.

use crate::config::Style;
use opencv::core::{Point, Scalar};

/// Colours are BGR, 0..255, before illumination.
#[derive(Clone, Debug)]
pub(super) struct Look {
    pub(super) plate: [f32; 3],
    /// Relative amplitude of the plate's smooth shading.
    pub(super) shading: f32,
    /// Fine grain, grey levels.
    pub(super) grain: f32,
    pub(super) brushed: bool,
    pub(super) body: [f32; 3],
    pub(super) body_alpha: f64,
    pub(super) marks: [f32; 3],
    pub(super) block: [f32; 3],
    pub(super) screw: [f32; 3],
    pub(super) wire: [f32; 3],
    pub(super) ball: [f32; 3],
    /// Illumination: level, gradient across x and y, vignetting.
    pub(super) light: [f32; 4],
    /// The whole scene is turned by this much in the image, degrees.
    pub(super) turn_deg: f64,
    pub(super) noise_sigma: f64,
}

impl Look {
    pub(super) fn of(style: Style) -> Self {
        match style {
            Style::DarkWire => Self {
                plate: [186.0, 190.0, 194.0],
                shading: 0.06,
                grain: 5.0,
                brushed: true,
                body: [236.0, 238.0, 236.0],
                body_alpha: 0.7,
                marks: [28.0, 28.0, 30.0],
                block: [92.0, 128.0, 160.0],
                screw: [55.0, 56.0, 60.0],
                wire: [34.0, 34.0, 38.0],
                ball: [150.0, 152.0, 156.0],
                light: [1.0, 0.07, 0.05, 0.14],
                turn_deg: 0.0,
                noise_sigma: 2.5,
            },
            Style::LightWire => Self {
                plate: [40.0, 37.0, 35.0],
                shading: 0.12,
                grain: 4.0,
                brushed: false,
                body: [70.0, 70.0, 68.0],
                body_alpha: 0.35,
                marks: [222.0, 224.0, 220.0],
                block: [72.0, 74.0, 78.0],
                screw: [165.0, 166.0, 170.0],
                wire: [228.0, 230.0, 232.0],
                ball: [175.0, 176.0, 180.0],
                light: [1.0, -0.06, 0.06, 0.2],
                turn_deg: 0.0,
                noise_sigma: 3.0,
            },
            Style::Oblique => Self {
                plate: [92.0, 102.0, 106.0],
                shading: 0.1,
                grain: 3.0,
                brushed: false,
                body: [132.0, 136.0, 138.0],
                body_alpha: 0.5,
                marks: [68.0, 70.0, 74.0],
                block: [78.0, 90.0, 100.0],
                screw: [45.0, 46.0, 50.0],
                wire: [50.0, 50.0, 54.0],
                ball: [120.0, 122.0, 126.0],
                light: [0.85, 0.5, 0.3, 0.3],
                turn_deg: 38.0,
                noise_sigma: 3.5,
            },
        }
    }
}

/// Illumination factor at pixel `(x, y)`.
pub(super) fn illumination(light: [f32; 4], x: f32, y: f32, w: f32, h: f32) -> f32 {
    let (u, v) = (x / w - 0.5, y / h - 0.5);
    let r2 = (u * u + v * v) * 2.0;
    light[0] * (1.0 + light[1] * u + light[2] * v) * (1.0 - light[3] * r2)
}

pub(super) fn pt(x: f64, y: f64) -> Point {
    // 4 fractional bits (drawing calls use shift = 4).
    Point::new((x * 16.0).round() as i32, (y * 16.0).round() as i32)
}

pub(super) fn bgr(c: [f32; 3]) -> Scalar {
    Scalar::new(c[0] as f64, c[1] as f64, c[2] as f64, 0.0)
}

pub(super) fn scale(c: [f32; 3], k: f32) -> [f32; 3] {
    [c[0] * k, c[1] * k, c[2] * k]
}

/// Round to the nearest grey level, saturating (`as` saturates; no `roundf` call).
#[inline]
pub(super) fn to_u8(v: f32) -> u8 {
    (v + 0.5) as u8
}

pub(super) fn mix(a: [f32; 3], b: [f32; 3], t: f32) -> [f32; 3] {
    [
        a[0] + (b[0] - a[0]) * t,
        a[1] + (b[1] - a[1]) * t,
        a[2] + (b[2] - a[2]) * t,
    ]
}
