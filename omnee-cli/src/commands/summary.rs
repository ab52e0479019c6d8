//! The result of `probe` and `estimate`: a JSON object, printed as it is
//! (`--json`) or as a few lines of text.

use omnee_render::technique::Resolved;
use serde_json::{Value, json};

/// The technique fields of a result: `technique`, `technique_requested`,
/// `auto_reason`.
pub fn technique_json(t: &Resolved) -> (Value, Value, Value) {
    (
        json!(t.used.to_string()),
        json!(t.requested.to_string()),
        json!(t.reason.map(|r| r.to_string())),
    )
}

/// Prints `v` (with `mean`, `stderr`, `samples`, `seconds`, `technique`,
/// optionally `auto_reason`, `terms` and `reference`) as JSON or as text.
pub fn print_result(v: &Value, as_json: bool) {
    if as_json {
        println!("{v}");
        return;
    }
    println!(
        "{} +- {} ({} samples, {:.3} s, technique {})",
        v["mean"],
        v["stderr"],
        v["samples"],
        v["seconds"].as_f64().unwrap_or(0.0),
        v["technique"]
    );
    if let Some(r) = v["auto_reason"].as_str() {
        println!("auto: {r}");
    }
    if let Some(terms) = v["terms"].as_object() {
        for (k, t) in terms {
            println!("  {k}: {} +- {}", t["mean"], t["stderr"]);
        }
    }
    if !v["reference"].is_null() {
        let kind = if v["technique"] == "bridge" {
            "closed form"
        } else {
            "quadrature"
        };
        println!("  reference ({kind}): {}", v["reference"]);
    }
}
