//! JSON pieces shared by the fixture generators (`fixtures_sh`, `fixtures_solid`).

/// A JSON string literal.
pub fn js(s: &str) -> String {
    serde_json::to_string(s).expect("a string serializes")
}

/// An f64 argument: shortest round-trip decimal and exact bit pattern.
pub fn arg_json(x: f64) -> String {
    format!(
        "{{\"decimal\": {}, \"bits\": {}}}",
        js(&format!("{x:?}")),
        js(&format!("{:#018x}", x.to_bits()))
    )
}
