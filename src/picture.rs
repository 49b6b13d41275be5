//! PNG pictures (Figure 11, the review frames, the gate's diagnostics), encoded and
//! decoded by the `png` crate: OpenCV is linked for `core` and `imgproc` only, so that
//! every `rollfric` process starts in a few milliseconds (OpenCV's `imgcodecs` and
//! `videoio` bring about 240 shared libraries to load with them, about 0.1 s per
//! process, which a workflow engine running one process per stage pays on every job).

use anyhow::{ensure, Context, Result};

/// The colour layout of a picture's bytes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Layout {
    /// One byte per pixel.
    Grey,
    /// Three bytes per pixel, blue first (OpenCV's order).
    Bgr,
}

impl Layout {
    fn channels(self) -> usize {
        match self {
            Layout::Grey => 1,
            Layout::Bgr => 3,
        }
    }
}

/// Encode `width` x `height` pixels (row-major, no padding) as a PNG, fast compression
/// (these pictures are looked at, not archived).
pub fn encode(width: usize, height: usize, layout: Layout, pixels: &[u8]) -> Result<Vec<u8>> {
    ensure!(
        width > 0 && height > 0 && pixels.len() == width * height * layout.channels(),
        "a {width}x{height} picture needs {} bytes, not {}",
        width * height * layout.channels(),
        pixels.len()
    );
    let mut out = Vec::new();
    {
        let w = u32::try_from(width).context("picture too wide")?;
        let h = u32::try_from(height).context("picture too tall")?;
        let mut enc = png::Encoder::new(&mut out, w, h);
        enc.set_depth(png::BitDepth::Eight);
        enc.set_compression(png::Compression::Fast);
        enc.set_color(match layout {
            Layout::Grey => png::ColorType::Grayscale,
            Layout::Bgr => png::ColorType::Rgb,
        });
        let mut writer = enc.write_header()?;
        match layout {
            Layout::Grey => writer.write_image_data(pixels)?,
            Layout::Bgr => {
                let rgb: Vec<u8> = pixels
                    .chunks_exact(3)
                    .flat_map(|p| [p[2], p[1], p[0]])
                    .collect();
                writer.write_image_data(&rgb)?
            }
        }
        writer.finish()?;
    }
    Ok(out)
}

/// Encode an OpenCV picture of 8-bit BGR pixels (as drawn for Figure 11 and the
/// diagnostics) as a PNG.
pub fn encode_bgr_mat(m: &opencv::core::Mat) -> Result<Vec<u8>> {
    use opencv::prelude::*;
    ensure!(
        m.typ() == opencv::core::CV_8UC3,
        "a picture of OpenCV type {}, not 8-bit BGR",
        m.typ()
    );
    encode(
        m.cols() as usize,
        m.rows() as usize,
        Layout::Bgr,
        m.data_bytes()?,
    )
}

/// A decoded picture: its size, layout and pixels (BGR for colour pictures).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Decoded {
    pub width: usize,
    pub height: usize,
    pub layout: Layout,
    pub pixels: Vec<u8>,
}

/// Decode an 8-bit grey or RGB PNG (as [`encode`] writes them).
pub fn decode(bytes: &[u8]) -> Result<Decoded> {
    let dec = png::Decoder::new(std::io::Cursor::new(bytes));
    let mut reader = dec.read_info().context("not a PNG")?;
    let mut buf = vec![0; reader.output_buffer_size().context("PNG too large")?];
    let info = reader.next_frame(&mut buf).context("a damaged PNG")?;
    buf.truncate(info.buffer_size());
    ensure!(
        info.bit_depth == png::BitDepth::Eight,
        "a PNG of {:?} bits per sample, not 8",
        info.bit_depth
    );
    let layout = match info.color_type {
        png::ColorType::Grayscale => Layout::Grey,
        png::ColorType::Rgb => {
            for p in buf.chunks_exact_mut(3) {
                p.swap(0, 2);
            }
            Layout::Bgr
        }
        other => anyhow::bail!("a PNG of colour type {other:?}, not grey or RGB"),
    };
    Ok(Decoded {
        width: info.width as usize,
        height: info.height as usize,
        layout,
        pixels: buf,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pictures_come_back_as_they_went_in() {
        let grey: Vec<u8> = (0..35).map(|v| (v * 7) as u8).collect();
        let d = decode(&encode(7, 5, Layout::Grey, &grey).unwrap()).unwrap();
        assert_eq!((d.width, d.height, d.layout), (7, 5, Layout::Grey));
        assert_eq!(d.pixels, grey);
        // Blue first in, blue first out; the file itself is RGB.
        let bgr: Vec<u8> = (0..3 * 6).map(|v| (v * 13) as u8).collect();
        let png = encode(3, 2, Layout::Bgr, &bgr).unwrap();
        let d = decode(&png).unwrap();
        assert_eq!((d.width, d.height, d.layout), (3, 2, Layout::Bgr));
        assert_eq!(d.pixels, bgr);
        // Stored as RGB, read by the png crate alone: pure blue in BGR is [0, 0, 255].
        let blue = encode(1, 1, Layout::Bgr, &[255, 0, 0]).unwrap();
        let mut reader = png::Decoder::new(std::io::Cursor::new(&blue[..]))
            .read_info()
            .unwrap();
        let mut raw = vec![0; reader.output_buffer_size().unwrap()];
        reader.next_frame(&mut raw).unwrap();
        assert_eq!(reader.info().color_type, png::ColorType::Rgb);
        assert_eq!(raw[..3], [0, 0, 255]);
        assert!(encode(3, 2, Layout::Bgr, &bgr[1..]).is_err());
        assert!(decode(&png[..20]).is_err());
    }
}
