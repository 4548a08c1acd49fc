//! Names derived from the input: the factor's snake-case name and the
//! readable spelling of a field type.

use quote::ToTokens;

/// `PointReprojection` → `point_reprojection`, `IMUPreintegration` →
/// `imu_preintegration`, `Se3Prior` → `se3_prior`.
pub fn snake_case(camel: &str) -> String {
    let chars: Vec<char> = camel.chars().collect();
    let mut out = String::with_capacity(camel.len() + 4);
    for (i, &c) in chars.iter().enumerate() {
        if c.is_uppercase() && i > 0 {
            let previous = chars[i - 1];
            let next_is_lower = chars.get(i + 1).is_some_and(|n| n.is_lowercase());
            let boundary = previous.is_lowercase()
                || previous.is_ascii_digit()
                || (previous.is_uppercase() && next_is_lower);
            if boundary && previous != '_' {
                out.push('_');
            }
        }
        out.extend(c.to_lowercase());
    }
    out
}

/// A type as the user would write it: `Se3<S>`, `SMatrix<S, 3, 1>`, `[S; 2]`.
pub fn type_text(ty: &impl ToTokens) -> String {
    let spaced = ty.to_token_stream().to_string();
    let mut out = String::with_capacity(spaced.len());
    let mut chars = spaced.chars().peekable();
    while let Some(c) = chars.next() {
        if c == ' ' {
            let previous = out.chars().last();
            let next = chars.peek().copied();
            let glue_after = matches!(previous, Some('<' | '&' | '(' | '[' | ':'));
            let glue_before = matches!(next, Some('<' | '>' | ',' | ';' | ')' | ']' | ':'));
            if glue_after || glue_before {
                continue;
            }
        }
        out.push(c);
    }
    out
}
