//! The run summary as JSON (`summary.json`).

use crate::metrics::Summary;

/// The summary as pretty-printed JSON, with a final newline.
pub fn summary_json(summary: &Summary) -> Result<String, serde_json::Error> {
    let mut s = serde_json::to_string_pretty(summary)?;
    s.push('\n');
    Ok(s)
}
