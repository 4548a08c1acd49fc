//! Helpers for derivations written as code ([`crate::Derivation`]): a
//! derivation's parameter list written from stored values
//! ([`Storage::to_scalars`]) and named from their layouts
//! ([`Storage::layout`]). The maps read the list back value by value with
//! [`factor_core::storage::ScalarReader`], in the same order. The audit from
//! a document's text names a symbols file's stored values the same way.

use factor_core::storage::Storage;

/// LaTeX names of the stored scalars of a `T` written `symbol`: its layout
/// names ([`factor_core::Layout::names`]) as subscripts, `T_{qx}`, `n_{w,x}`
/// (a subscript the symbol already has comes first). A record's names are
/// cut to their last part (`rotation.qx` to `qx`) when those stay distinct;
/// a lone scalar is the symbol itself. Without a symbol, the names are the
/// layout's own, upright (`\mathrm{body_pose.rotation.qx}`).
pub fn stored_names<T: Storage<f64>>(symbol: &str) -> Vec<String> {
    let names = T::layout().names();
    if names.len() == 1 && names[0] == "value" {
        return vec![symbol.to_owned()];
    }
    if symbol.is_empty() {
        return names
            .iter()
            .map(|n| format!("\\mathrm{{{}}}", n.replace('_', "\\_")))
            .collect();
    }
    let last: Vec<&str> = names
        .iter()
        .map(|n| n.rsplit('.').next().unwrap_or(n))
        .collect();
    let distinct = last.iter().enumerate().all(|(i, n)| !last[..i].contains(n));
    let (base, sub) = match symbol.split_once('_') {
        Some((base, sub)) => (base, format!("{},", sub.trim_matches(['{', '}']))),
        None => (symbol, String::new()),
    };
    names
        .iter()
        .zip(last)
        .map(|(name, short)| {
            let part = if distinct { short } else { name.as_str() };
            format!("{base}_{{{sub}{part}}}")
        })
        .collect()
}

/// A derivation's parameters, built value by value: each value's stored
/// scalars, named by [`stored_names`].
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Parameters(Vec<(String, f64)>);

impl Parameters {
    /// No parameters.
    pub fn new() -> Self {
        Parameters::default()
    }

    /// Appends the stored scalars of `value`, written `symbol`.
    pub fn with<T: Storage<f64>>(mut self, symbol: &str, value: &T) -> Self {
        self.0.extend(
            stored_names::<T>(symbol)
                .into_iter()
                .zip(value.to_scalars()),
        );
        self
    }
}

impl From<Parameters> for Vec<(String, f64)> {
    fn from(p: Parameters) -> Self {
        p.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use factor_core::geometry::PluckerLine;
    use factor_core::lie::Se3;
    use nalgebra::Vector3;

    #[test]
    fn names_come_from_the_layout() {
        assert_eq!(
            stored_names::<Se3<f64>>("T"),
            [
                "T_{qx}", "T_{qy}", "T_{qz}", "T_{qw}", "T_{x}", "T_{y}", "T_{z}"
            ]
        );
        assert_eq!(
            stored_names::<Vector3<f64>>("n_w"),
            ["n_{w,x}", "n_{w,y}", "n_{w,z}"]
        );
        assert_eq!(stored_names::<f64>("d_L"), ["d_L"]);
        assert_eq!(stored_names::<Vector3<f64>>("")[0], "\\mathrm{x}");
        // Parts whose last names repeat keep their whole path.
        assert_eq!(stored_names::<PluckerLine<f64>>("L")[3], "L_{direction.x}");
    }

    #[test]
    fn parameters_are_the_stored_scalars_in_order() {
        let v = Vector3::new(1.0, 2.0, 3.0);
        let p: Vec<(String, f64)> = Parameters::new().with("x", &v).with("d", &4.0).into();
        let values: Vec<f64> = p.iter().map(|(_, v)| *v).collect();
        assert_eq!(values, [1.0, 2.0, 3.0, 4.0]);
        assert_eq!(p[3].0, "d");
    }
}
