//! The `variables` and `constants` objects of an `eval` request → the
//! factor, for any factor: each field is read in the shape its type's
//! [`Storage::input_layout`](factor_core::Storage::input_layout) gives (an
//! object for a record, an array for named scalars, a number), then checked
//! and converted to its stored scalars by its type's
//! [`Storage::from_input`](factor_core::Storage::from_input) (unit
//! quaternions within
//! [`QUATERNION_NORM_TOLERANCE`](factor_core::storage::QUATERNION_NORM_TOLERANCE)
//! of norm 1, planes at any
//! scale, Plücker lines to the orthonormal form, ...). Errors name the field
//! path (exit 2); what only the factor can judge (a point behind the camera,
//! parallel bearings, ...) is left to its `validate()`.

use factor_core::{Factor, FieldInfo, Layout, StorageError};

use crate::error::InputError;
use crate::field_path::join;
use crate::input::Object;

/// The JSON shape of a layout, for `list` and error messages:
/// `{"rotation": [qx, qy, qz, qw], "translation": [x, y, z]}`.
pub fn json_shape(layout: &Layout) -> String {
    match layout {
        Layout::Scalar => "number".to_owned(),
        Layout::Array(names) => format!("[{}]", names.join(", ")),
        Layout::Record(parts) => {
            let parts: Vec<String> = parts
                .iter()
                .map(|(key, part)| format!("\"{key}\": {}", json_shape(part)))
                .collect();
            format!("{{{}}}", parts.join(", "))
        }
    }
}

/// The keys of a record layout (none for another layout).
pub fn record_keys(layout: &Layout) -> Vec<&'static str> {
    match layout {
        Layout::Record(parts) => parts.iter().map(|(key, _)| *key).collect(),
        Layout::Scalar | Layout::Array(_) => Vec::new(),
    }
}

/// Whether an array of these names is a quaternion (the layout of
/// [`factor_core::lie::Quaternion`]): read through [`Object::quaternion`], which
/// can try the `[w, x, y, z]` order for the w-first hint.
fn is_quaternion(names: &[String]) -> bool {
    names == ["qx", "qy", "qz", "qw"]
}

/// Appends the numbers of field `key` of `object`, written in `layout`, to `out`.
fn read(object: &Object, key: &str, layout: &Layout, out: &mut Vec<f64>) -> Result<(), InputError> {
    match layout {
        Layout::Scalar => out.push(object.number(key)?),
        Layout::Array(names) if is_quaternion(names) => object.quaternion_into(key, out)?,
        Layout::Array(names) => object.numbers_into(key, names.len(), out)?,
        Layout::Record(parts) => {
            let inner = object.object(key, &record_keys(layout))?;
            for (part_key, part) in parts {
                read(&inner, part_key, part, out)?;
            }
        }
    }
    Ok(())
}

/// Field `field`'s stored scalars from `object` (the request's `variables`
/// or `constants`), its input read into `input`.
fn field_scalars(
    object: &Object,
    field: &FieldInfo,
    input: &mut Vec<f64>,
) -> Result<Vec<f64>, InputError> {
    input.clear();
    read(object, field.name, &field.input_layout, input)?;
    (field.from_input)(input).map_err(|e| at_part(object.path_of(field.name), e))
}

/// The type's refusal `error` of the value at `path`, at the part of it at
/// fault (`…rotation`, `…[2]`).
pub fn at_part(mut path: String, error: StorageError) -> InputError {
    if !error.path.is_empty() {
        for part in error.path.split('.') {
            path = match part.strip_prefix('[') {
                Some(_) => format!("{path}{part}"),
                None => join(&path, part),
            };
        }
    }
    InputError::new(path, error.message)
}

/// The stored scalars of the factor whose fields are `fields` (in
/// declaration order) from its checked `variables` and `constants` objects
/// (each with exactly its variable and constant fields): what a tool that
/// hands a factor to another solver (its generated C++, say) reads a
/// problem file's entry into.
pub fn stored_scalars(
    fields: &[FieldInfo],
    variables: &Object,
    constants: &Object,
) -> Result<Vec<f64>, InputError> {
    let mut stored = Vec::with_capacity(fields.iter().map(|f| f.scalars).sum());
    let mut input = Vec::new();
    for field in fields {
        let object = if field.variable.is_some() {
            variables
        } else {
            constants
        };
        stored.extend(field_scalars(object, field, &mut input)?);
    }
    Ok(stored)
}

/// Factor `F` from its checked `variables` and `constants` objects (each
/// with exactly `F`'s variable and constant fields).
pub fn decode<F: Factor>(variables: &Object, constants: &Object) -> Result<F, InputError> {
    decode_with(&F::fields(), variables, constants)
}

/// [`decode`] with `F`'s `fields` given (from a `FieldsCache`).
pub fn decode_with<F: Factor>(
    fields: &[FieldInfo],
    variables: &Object,
    constants: &Object,
) -> Result<F, InputError> {
    let stored = stored_scalars(fields, variables, constants)?;
    Ok(F::from_scalars(&stored))
}

/// Each factor type's fields and its variables' tangent dimensions, built
/// once: [`Factor::fields`] and [`Factor::variables`] build them (their
/// layouts' names as strings) anew at every call, and a problem file
/// decodes thousands of factors of a few types (`solve`).
#[derive(Default)]
pub struct FieldsCache {
    fields: std::collections::HashMap<std::any::TypeId, std::sync::Arc<[FieldInfo]>>,
    tangents: std::collections::HashMap<std::any::TypeId, std::sync::Arc<[usize]>>,
}

impl FieldsCache {
    /// `F`'s fields.
    pub fn of<F: Factor + 'static>(&mut self) -> std::sync::Arc<[FieldInfo]> {
        let fields = self.fields.entry(std::any::TypeId::of::<F>());
        std::sync::Arc::clone(fields.or_insert_with(|| F::fields().into()))
    }

    /// The tangent dimension of each of `F`'s variables, in order.
    pub fn tangent_dims<F: Factor + 'static>(&mut self) -> std::sync::Arc<[usize]> {
        let dims = self.tangents.entry(std::any::TypeId::of::<F>());
        std::sync::Arc::clone(
            dims.or_insert_with(|| F::variables().iter().map(|v| v.tangent_dim).collect()),
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The cache hands out each type's fields as `Factor::fields` builds
    /// them, built once per type.
    #[test]
    fn the_cache_holds_each_types_fields() {
        use slam_factors::{BetweenFactor, PointReprojection};
        let shown = |fields: &[FieldInfo]| -> Vec<(&str, usize, Option<usize>, String)> {
            fields
                .iter()
                .map(|f| (f.name, f.scalars, f.variable, json_shape(&f.input_layout)))
                .collect()
        };
        let mut cache = FieldsCache::default();
        let first = cache.of::<PointReprojection>();
        assert_eq!(shown(&first), shown(&PointReprojection::fields()));
        let between = cache.of::<BetweenFactor>();
        assert_eq!(shown(&between), shown(&BetweenFactor::fields()));
        assert!(std::sync::Arc::ptr_eq(
            &first,
            &cache.of::<PointReprojection>()
        ));
        let dims: Vec<usize> = PointReprojection::variables()
            .iter()
            .map(|v| v.tangent_dim)
            .collect();
        assert_eq!(*cache.tangent_dims::<PointReprojection>(), dims[..]);
    }
}
