//! JSON → typed values. Every error names the offending field by its path
//! (`variables.pose.rotation[3]`, shown as [`crate::field_path`] says) and
//! says what is wrong, in one line.
//!
//! Objects are closed: a key that is not expected is an error at every level,
//! as is a missing one. Numbers are finite: [`crate::strict_json`] rejects
//! literals beyond the `f64` range as it reads them. Values are read from
//! a [`crate::document::Document`].

use std::cell::RefCell;

use crate::document::{Json, Members};
use crate::error::InputError;
use crate::field_path::{self, join};

/// How [`Object::quaternion`] reads quaternions: it records the path of each
/// one it reads, and reads those at the paths given to
/// [`QuaternionReading::w_first`] as `[w, x, y, z]` (to try whether an input
/// was written in that order).
#[derive(Debug, Default)]
pub struct QuaternionReading {
    w_first: Vec<String>,
    read: RefCell<Vec<String>>,
}

impl QuaternionReading {
    /// Reads the quaternions at `paths` as `[w, x, y, z]`, the others as `[x, y, z, w]`.
    pub fn w_first(paths: &[String]) -> Self {
        QuaternionReading {
            w_first: paths.to_vec(),
            read: RefCell::default(),
        }
    }

    /// The paths of the quaternions read so far, in reading order.
    pub fn read(&self) -> Vec<String> {
        self.read.borrow().clone()
    }
}

/// A finite number at `path`.
pub fn number(value: Json<'_>, path: &str) -> Result<f64, InputError> {
    value
        .as_f64()
        .ok_or_else(|| InputError::new(path, format!("expected a number, found {}", value.kind())))
}

/// An array of exactly `n` finite numbers at `path`.
pub fn numbers(value: Json<'_>, path: &str, n: usize) -> Result<Vec<f64>, InputError> {
    numbers_at(value, n, || path.to_owned())
}

/// [`numbers`] with the path made only for an error.
fn numbers_at(
    value: Json<'_>,
    n: usize,
    path: impl FnOnce() -> String,
) -> Result<Vec<f64>, InputError> {
    if let Some(items) = value.as_array().filter(|items| items.len() == n)
        && let Some(numbers) = items.iter().map(Json::as_f64).collect::<Option<Vec<f64>>>()
    {
        return Ok(numbers);
    }
    let path = path();
    let items = value.as_array().ok_or_else(|| {
        InputError::new(
            &path,
            format!("expected an array of {n} numbers, found {}", value.kind()),
        )
    })?;
    if items.len() != n {
        return Err(InputError::new(
            path,
            format!("wrong length: expected {n} numbers, found {}", items.len()),
        ));
    }
    items
        .iter()
        .enumerate()
        .map(|(i, item)| number(item, &field_path::index(&path, i)))
        .collect()
}

/// A JSON object whose keys have been checked: none unknown, none missing.
#[derive(Debug, Clone)]
pub struct Object<'a> {
    path: String,
    fields: Fields<'a>,
    quaternions: Option<&'a QuaternionReading>,
}

/// Where an [`Object`]'s fields are: a JSON object, or values gathered
/// from elsewhere under the object's keys ([`Object::gathered`]).
#[derive(Debug, Clone)]
enum Fields<'a> {
    Map(Members<'a>),
    Gathered(Vec<(&'a str, Json<'a>)>),
}

impl<'a> Object<'a> {
    /// Checks that `value` (at `path`, `""` for the top level) is an object
    /// with exactly the fields `keys`.
    pub fn new(value: Json<'a>, path: &str, keys: &[&str]) -> Result<Self, InputError> {
        let expected = || keys.join(", ");
        let map = value.as_object().ok_or_else(|| {
            let at = if path.is_empty() { "input" } else { path };
            InputError::new(
                at,
                format!(
                    "expected an object with fields {}, found {}",
                    expected(),
                    value.kind()
                ),
            )
        })?;
        // Exactly the keys: as many, each present (the slow search for
        // the culprit runs only when not).
        if map.len() != keys.len() || !keys.iter().all(|k| map.contains_key(k)) {
            if let Some(unknown) = map.keys().find(|k| !keys.contains(k)) {
                return Err(InputError::new(
                    join(path, unknown),
                    format!("unknown field; expected only {}", expected()),
                ));
            }
            if let Some(missing) = keys.iter().find(|k| !map.contains_key(k)) {
                return Err(InputError::new(join(path, missing), "missing field"));
            }
        }
        Ok(Object {
            path: path.into(),
            fields: Fields::Map(map),
            quaternions: None,
        })
    }

    /// The object at `path` whose fields are the values `fields`, by key,
    /// read from elsewhere (a factor entry's variable fields, each the
    /// value of the variable it names).
    pub fn gathered(path: &str, fields: Vec<(&'a str, Json<'a>)>) -> Self {
        Object {
            path: path.into(),
            fields: Fields::Gathered(fields),
            quaternions: None,
        }
    }

    /// Like [`Object::new`] for the top level, reading its quaternions (and
    /// those of its sub-objects) as `quaternions` says.
    pub fn top(
        value: Json<'a>,
        keys: &[&str],
        quaternions: &'a QuaternionReading,
    ) -> Result<Self, InputError> {
        Ok(Object {
            quaternions: Some(quaternions),
            ..Object::new(value, "", keys)?
        })
    }

    /// The path of field `key`.
    pub fn path_of(&self, key: &str) -> String {
        join(&self.path, key)
    }

    /// The value of field `key` (checked present by [`Object::new`]).
    pub fn get(&self, key: &str) -> Json<'a> {
        let value = match &self.fields {
            Fields::Map(map) => map.get(key),
            Fields::Gathered(fields) => fields.iter().find(|(k, _)| *k == key).map(|(_, v)| *v),
        };
        value.unwrap_or_else(|| panic!("no field {key}"))
    }

    /// A string field.
    pub fn string(&self, key: &str) -> Result<&'a str, InputError> {
        let value = self.get(key);
        value.as_str().ok_or_else(|| {
            InputError::new(
                self.path_of(key),
                format!("expected a string, found {}", value.kind()),
            )
        })
    }

    /// A finite number field.
    pub fn number(&self, key: &str) -> Result<f64, InputError> {
        let value = self.get(key);
        value
            .as_f64()
            .map_or_else(|| number(value, &self.path_of(key)), Ok)
    }

    /// A field holding an array of `n` finite numbers.
    pub fn numbers(&self, key: &str, n: usize) -> Result<Vec<f64>, InputError> {
        numbers_at(self.get(key), n, || self.path_of(key))
    }

    /// [`Object::numbers`] appended to `out`.
    pub(crate) fn numbers_into(
        &self,
        key: &str,
        n: usize,
        out: &mut Vec<f64>,
    ) -> Result<(), InputError> {
        let value = self.get(key);
        if let Some(items) = value.as_array().filter(|items| items.len() == n) {
            let start = out.len();
            out.extend(items.iter().map_while(Json::as_f64));
            if out.len() == start + n {
                return Ok(());
            }
            out.truncate(start);
        }
        out.extend(numbers_at(value, n, || self.path_of(key))?);
        Ok(())
    }

    /// [`Object::quaternion`] appended to `out`.
    pub(crate) fn quaternion_into(&self, key: &str, out: &mut Vec<f64>) -> Result<(), InputError> {
        let start = out.len();
        self.numbers_into(key, 4, out)?;
        if let Some(reading) = self.quaternions {
            let path = self.path_of(key);
            if reading.w_first.contains(&path) {
                out[start..].rotate_left(1);
            }
            reading.read.borrow_mut().push(path);
        }
        Ok(())
    }

    /// A field holding a quaternion's four numbers, returned `[x, y, z, w]`:
    /// as written, or read `[w, x, y, z]` where the [`QuaternionReading`]
    /// says so; the reading records the field's path. Whether it is a unit
    /// quaternion is for its type to judge
    /// ([`factor_core::Storage::from_input`]).
    pub fn quaternion(&self, key: &str) -> Result<Vec<f64>, InputError> {
        let mut c = Vec::with_capacity(4);
        self.quaternion_into(key, &mut c)?;
        Ok(c)
    }

    /// A sub-object with exactly the fields `keys`.
    pub fn object(&self, key: &str, keys: &[&str]) -> Result<Object<'a>, InputError> {
        Ok(Object {
            quaternions: self.quaternions,
            ..Object::new(self.get(key), &self.path_of(key), keys)?
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::document::Document;

    fn document(value: serde_json::Value) -> Document {
        Document::from_value(&value)
    }

    #[test]
    fn paths_of_unusual_keys_are_quoted() {
        let value = document(serde_json::json!({"v": {"a\nb": 1}}));
        let top = Object::new(value.root(), "", &["v"]).unwrap();
        let error = top.object("v", &["c"]).unwrap_err();
        assert_eq!(error.path, "v[\"a\\nb\"]");
        let error = numbers(document(serde_json::json!([1, "x"])).root(), "", 2).unwrap_err();
        assert_eq!(error.path, "input[1]");
    }

    /// An object gathered from values elsewhere reads them as the object
    /// of those fields would, its errors at its own path.
    #[test]
    fn a_gathered_object_reads_its_fields_as_an_object_would() {
        let (a, b) = (
            document(serde_json::json!([1.0, 2.0])),
            document(serde_json::json!({"x": 3.0})),
        );
        let gathered = Object::gathered("f.variables", vec![("a", a.root()), ("b", b.root())]);
        assert_eq!(gathered.numbers("a", 2).unwrap(), [1.0, 2.0]);
        let b = gathered.object("b", &["x"]).unwrap();
        assert_eq!(b.number("x").unwrap(), 3.0);
        let error = gathered.numbers("a", 3).unwrap_err();
        assert_eq!(error.path, "f.variables.a");
        assert_eq!(gathered.string("b").unwrap_err().path, "f.variables.b");
    }

    #[test]
    fn quaternions_are_read_w_first_where_asked_and_recorded() {
        let value = document(
            serde_json::json!({"p": {"q": [1.0, 0.0, 0.0, 0.0], "r": [1.0, 0.0, 0.0, 0.0]}}),
        );
        let reading = QuaternionReading::w_first(&["p.q".to_owned()]);
        let top = Object::top(value.root(), &["p"], &reading).unwrap();
        let p = top.object("p", &["q", "r"]).unwrap();
        assert_eq!(p.quaternion("q").unwrap(), [0.0, 0.0, 0.0, 1.0]);
        assert_eq!(p.quaternion("r").unwrap(), [1.0, 0.0, 0.0, 0.0]);
        assert_eq!(reading.read(), ["p.q", "p.r"]);
    }
}
