//! The system OpenCV, seen from the tool: its version and video back-ends.

use anyhow::Result;
use opencv::videoio;

/// Tool version, OpenCV version and the video back-ends this OpenCV build offers.
pub fn info() -> Result<String> {
    let backends = videoio::get_backends()?
        .iter()
        .map(|b| videoio::get_backend_name(b).unwrap_or_else(|_| format!("{b:?}")))
        .collect::<Vec<_>>()
        .join(", ");
    let writers = videoio::get_writer_backends()?
        .iter()
        .map(|b| videoio::get_backend_name(b).unwrap_or_else(|_| format!("{b:?}")))
        .collect::<Vec<_>>()
        .join(", ");
    Ok(format!(
        "rollfric {}\nOpenCV {}\nvideo readers: {backends}\nvideo writers: {writers}\n",
        env!("CARGO_PKG_VERSION"),
        opencv::core::CV_VERSION,
    ))
}
