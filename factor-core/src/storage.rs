//! Storage: how a value is kept as a fixed list of named scalars.
//!
//! Every type a factor holds (scalars, vectors, Lie groups, the documents'
//! landmarks, and a derived factor itself) implements [`Storage`]: it says
//! how many scalars it stores, names them ([`Layout`]), and converts to and
//! from the flat list. That one description is what
//!
//! - lifts an `f64` factor to dual numbers ([`Storage::map_scalars`]),
//! - builds a factor over symbols for the code generator
//!   ([`Storage::from_scalars`]),
//! - lays out a generated kernel's input arrays (one array per field, its
//!   scalars in storage order, documented by the layout),
//! - reads values a user writes (JSON on the command line, data files):
//!   [`Storage::input_layout`] is the shape they write, and
//!   [`Storage::from_input`] checks it and converts it to the stored scalars
//!   (a quaternion within [`QUATERNION_NORM_TOLERANCE`] of unit norm is
//!   re-normalised; a plane may be given at any scale),
//! - and reads consecutive values out of one flat parameter list
//!   ([`ScalarReader`]).

use std::fmt;

use nalgebra::{SMatrix, SVector, Unit};

use crate::scalar::Scalar;

/// How far from 1 the norm of a quaternion given by a user may be; within it
/// [`Storage::from_input`] re-normalises it, beyond it rejects it.
pub const QUATERNION_NORM_TOLERANCE: f64 = 1e-6;

/// The names and grouping of a value's stored scalars, in storage order.
///
/// A user writes a value in this shape: a [`Layout::Record`] as an object
/// with exactly those keys, a [`Layout::Array`] as an array of that many
/// numbers, a [`Layout::Scalar`] as a number.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Layout {
    /// One scalar.
    Scalar,
    /// Named scalars in order (`[x, y, z]`, `[x, y, z, w]`, `[fu, fv, cu, cv]`).
    Array(Vec<String>),
    /// Named parts in order (`{rotation: [x, y, z, w], translation: [x, y, z]}`).
    Record(Vec<(&'static str, Layout)>),
}

impl Layout {
    /// An array of the given names.
    pub fn array(names: &[&str]) -> Layout {
        Layout::Array(names.iter().map(|n| (*n).to_owned()).collect())
    }

    /// The number of scalars.
    pub fn scalars(&self) -> usize {
        match self {
            Layout::Scalar => 1,
            Layout::Array(names) => names.len(),
            Layout::Record(parts) => parts.iter().map(|(_, part)| part.scalars()).sum(),
        }
    }

    /// Every scalar's name in storage order, parts joined by dots
    /// (`rotation.x`); a lone scalar is named by its record key, or `value`.
    pub fn names(&self) -> Vec<String> {
        match self {
            Layout::Scalar => vec!["value".to_owned()],
            Layout::Array(names) => names.clone(),
            Layout::Record(parts) => parts
                .iter()
                .flat_map(|(key, part)| match part {
                    Layout::Scalar => vec![(*key).to_owned()],
                    _ => part
                        .names()
                        .into_iter()
                        .map(|name| format!("{key}.{name}"))
                        .collect(),
                })
                .collect(),
        }
    }
}

/// `number`, `[x, y, z]`, `{rotation: [x, y, z, w], distance}`.
impl fmt::Display for Layout {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Layout::Scalar => f.write_str("number"),
            Layout::Array(names) => write!(f, "[{}]", names.join(", ")),
            Layout::Record(parts) => {
                f.write_str("{")?;
                for (i, (key, part)) in parts.iter().enumerate() {
                    if i > 0 {
                        f.write_str(", ")?;
                    }
                    match part {
                        Layout::Scalar => f.write_str(key)?,
                        _ => write!(f, "{key}: {part}")?,
                    }
                }
                f.write_str("}")
            }
        }
    }
}

/// Scalars a user gave that do not describe a value of the type: where,
/// relative to the value (`rotation`, `[0]`, or empty for the whole), and what.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("{}{message}", if path.is_empty() { String::new() } else { format!("{path}: ") })]
pub struct StorageError {
    /// The part of the value at fault, relative to it (`""` for the whole).
    pub path: String,
    /// What is wrong, one line.
    pub message: String,
}

impl StorageError {
    /// An error about the whole value.
    pub fn new(message: impl Into<String>) -> Self {
        StorageError {
            path: String::new(),
            message: message.into(),
        }
    }

    /// The same error seen from a value holding this one as part `key`
    /// (`rotation` then `x` gives `rotation.x`; an index `[3]` is appended).
    pub fn within(mut self, key: &str) -> Self {
        self.path = match (self.path.is_empty(), self.path.starts_with('[')) {
            (true, _) => key.to_owned(),
            (false, true) => format!("{key}{}", self.path),
            (false, false) => format!("{key}.{}", self.path),
        };
        self
    }
}

/// A value stored as a fixed list of scalars, which can be rebuilt over
/// another scalar type: `f64` values are lifted to dual numbers or to
/// symbols this way. See the module documentation for what uses it.
#[diagnostic::on_unimplemented(
    message = "`{Self}` cannot be a factor's field: it does not implement `Storage<{S}>`",
    label = "not stored as scalars of `{S}`",
    note = "a field is written over the factor's scalar `{S}`: `{S}`, `[{S}; N]`, nalgebra's \
            `SVector<{S}, N>` and `SMatrix<{S}, R, C>`, `factor_core`'s geometry and Lie types, \
            or a type of yours implementing `factor_core::Storage<{S}>` (see its documentation)"
)]
pub trait Storage<S: Scalar>: Sized {
    /// The same value type over scalar `T`.
    type With<T: Scalar>;
    /// How many scalars are stored.
    const SCALARS: usize;

    /// The stored scalars' names and grouping; `layout().scalars() == SCALARS`.
    fn layout() -> Layout;

    /// Rebuilds the value with every stored scalar passed through `f`, in
    /// storage order.
    fn map_scalars<T: Scalar>(&self, f: &mut impl FnMut(S) -> T) -> Self::With<T>;

    /// Builds a value from its stored scalars: `next` is called
    /// [`Storage::SCALARS`] times, in storage order. No check is made (a
    /// quaternion is taken as it is): values from users go through
    /// [`Storage::from_input`] first.
    fn read_scalars(next: &mut impl FnMut() -> S) -> Self;

    /// The shape in which a user writes the value (JSON, data files): by
    /// default the storage [`Storage::layout`]. A type stored in a form
    /// users do not write (an orthonormal line, written as Plücker
    /// coordinates) names the form they do.
    fn input_layout() -> Layout {
        Self::layout()
    }

    /// The stored scalars of the value a user wrote as `input` (in
    /// [`Storage::input_layout`] order, `input.len()` equal to its
    /// [`Layout::scalars`]), checked and canonicalised: what does not
    /// describe a value of the type is an error naming the part at fault.
    /// By default every list of finite numbers is a value, stored as given.
    fn from_input(input: &[f64]) -> Result<Vec<f64>, StorageError> {
        Ok(input.to_vec())
    }

    /// Writes the stored scalars, in order, into `out` (no allocation).
    ///
    /// # Panics
    ///
    /// If `out.len()` is not [`Storage::SCALARS`].
    fn write_scalars(&self, out: &mut [S]) {
        assert_eq!(
            out.len(),
            Self::SCALARS,
            "a value of this type stores {} scalars",
            Self::SCALARS
        );
        let mut slots = out.iter_mut();
        self.map_scalars(&mut |s| {
            if let Some(slot) = slots.next() {
                *slot = s;
            }
            s
        });
    }

    /// The stored scalars in order.
    fn to_scalars(&self) -> Vec<S> {
        let mut out = vec![S::zero(); Self::SCALARS];
        self.write_scalars(&mut out);
        out
    }

    /// The value stored as `stored`.
    ///
    /// # Panics
    ///
    /// If `stored.len()` is not [`Storage::SCALARS`].
    fn from_scalars(stored: &[S]) -> Self {
        assert_eq!(
            stored.len(),
            Self::SCALARS,
            "a value of this type stores {} scalars",
            Self::SCALARS
        );
        let mut values = stored.iter().copied();
        Self::read_scalars(&mut || values.next().expect("length checked above"))
    }
}

/// Reads consecutive values out of one flat list of stored scalars (a
/// derivation's parameters, a kernel's inputs).
#[derive(Debug, Clone)]
pub struct ScalarReader<'a, S> {
    rest: &'a [S],
}

impl<'a, S: Scalar> ScalarReader<'a, S> {
    /// A reader at the start of `scalars`.
    pub fn new(scalars: &'a [S]) -> Self {
        ScalarReader { rest: scalars }
    }

    /// The next value of type `T`.
    ///
    /// # Panics
    ///
    /// If fewer than `T::SCALARS` scalars are left.
    pub fn read<T: Storage<S>>(&mut self) -> T {
        assert!(
            self.rest.len() >= T::SCALARS,
            "{} scalars left, a value needs {}",
            self.rest.len(),
            T::SCALARS
        );
        let (head, tail) = self.rest.split_at(T::SCALARS);
        self.rest = tail;
        T::from_scalars(head)
    }

    /// The scalars not read yet.
    pub fn rest(&self) -> &'a [S] {
        self.rest
    }
}

/// Scalars store themselves.
impl<S: Scalar> Storage<S> for S {
    type With<T: Scalar> = T;
    const SCALARS: usize = 1;
    fn layout() -> Layout {
        Layout::Scalar
    }
    fn map_scalars<T: Scalar>(&self, f: &mut impl FnMut(S) -> T) -> T {
        f(*self)
    }
    fn read_scalars(next: &mut impl FnMut() -> S) -> S {
        next()
    }
}

/// Fixed-size vectors and matrices store their entries in nalgebra's
/// column-major order: a vector's entries in order, named `x, y, z, w` up
/// to four, else by index.
impl<S: Scalar, const R: usize, const C: usize> Storage<S> for SMatrix<S, R, C> {
    type With<T: Scalar> = SMatrix<T, R, C>;
    const SCALARS: usize = R * C;
    fn layout() -> Layout {
        const XYZW: [&str; 4] = ["x", "y", "z", "w"];
        Layout::Array(match (R, C) {
            (r, 1) if r <= 4 => XYZW[..r].iter().map(|n| (*n).to_owned()).collect(),
            (r, 1) => (0..r).map(|i| i.to_string()).collect(),
            _ => (0..C)
                .flat_map(|c| (0..R).map(move |r| format!("m{r}{c}")))
                .collect(),
        })
    }
    fn map_scalars<T: Scalar>(&self, f: &mut impl FnMut(S) -> T) -> SMatrix<T, R, C> {
        SMatrix::<T, R, C>::from_iterator(self.iter().map(|&s| f(s)))
    }
    fn read_scalars(next: &mut impl FnMut() -> S) -> Self {
        SMatrix::<S, R, C>::from_iterator(std::iter::repeat_with(next).take(R * C))
    }
}

/// A unit vector stores its entries as a vector does (and is read back as
/// stored, unchecked); users give it at any non-zero scale, normalised by
/// [`crate::linalg::unit_of`] over the whole `f64` range: a direction (a
/// bearing) or a homogeneous vector (a plane `[a, b, c, d]`).
impl<S: Scalar, const R: usize> Storage<S> for Unit<SVector<S, R>> {
    type With<T: Scalar> = Unit<SVector<T, R>>;
    const SCALARS: usize = R;
    fn layout() -> Layout {
        <SVector<S, R> as Storage<S>>::layout()
    }
    fn map_scalars<T: Scalar>(&self, f: &mut impl FnMut(S) -> T) -> Unit<SVector<T, R>> {
        Unit::new_unchecked(self.as_ref().map_scalars(f))
    }
    fn read_scalars(next: &mut impl FnMut() -> S) -> Self {
        Unit::new_unchecked(SVector::read_scalars(next))
    }
    fn from_input(input: &[f64]) -> Result<Vec<f64>, StorageError> {
        let v = SVector::<f64, R>::from_column_slice(input);
        crate::linalg::unit_of(&v)
            .map(|unit| unit.as_slice().to_vec())
            .ok_or_else(|| StorageError::new("zero vector: it has no direction"))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::{Matrix2, Vector2, Vector3};

    #[test]
    fn vectors_store_their_entries_in_order() {
        let v = Vector3::new(1.0_f64, 2.0, 3.0);
        assert_eq!(v.to_scalars(), vec![1.0, 2.0, 3.0]);
        assert_eq!(Vector3::<f64>::from_scalars(&[1.0, 2.0, 3.0]), v);
        assert_eq!(
            <Vector3<f64> as Storage<f64>>::layout().to_string(),
            "[x, y, z]"
        );
    }

    #[test]
    fn matrices_store_column_major() {
        let m = Matrix2::new(1.0_f64, 2.0, 3.0, 4.0);
        assert_eq!(m.to_scalars(), vec![1.0, 3.0, 2.0, 4.0]);
        assert_eq!(Matrix2::<f64>::from_scalars(&m.to_scalars()), m);
        assert_eq!(
            <Matrix2<f64> as Storage<f64>>::layout().names(),
            ["m00", "m10", "m01", "m11"]
        );
    }

    #[test]
    fn map_scalars_changes_the_scalar_type_in_storage_order() {
        let v = Vector2::new(1.0_f64, 2.0);
        let w: Vector2<f32> = v.map_scalars(&mut |s| s as f32 * 2.0);
        assert_eq!(w, Vector2::new(2.0_f32, 4.0));
    }

    #[test]
    fn readers_take_consecutive_values() {
        let scalars = [1.0, 2.0, 3.0, 4.0, 5.0, 6.0];
        let mut reader = ScalarReader::new(&scalars);
        let a: Vector2<f64> = reader.read();
        let b: f64 = reader.read();
        assert_eq!((a, b), (Vector2::new(1.0, 2.0), 3.0));
        assert_eq!(reader.rest(), &[4.0, 5.0, 6.0]);
    }

    #[test]
    fn layouts_name_nested_parts() {
        let layout = Layout::Record(vec![
            ("rotation", Layout::array(&["qx", "qy", "qz", "qw"])),
            ("distance", Layout::Scalar),
        ]);
        assert_eq!(layout.to_string(), "{rotation: [qx, qy, qz, qw], distance}");
        assert_eq!(layout.scalars(), 5);
        assert_eq!(
            layout.names(),
            [
                "rotation.qx",
                "rotation.qy",
                "rotation.qz",
                "rotation.qw",
                "distance"
            ]
        );
        let error = StorageError::new("bad").within("rotation").within("line");
        assert_eq!(error.to_string(), "line.rotation: bad");
    }

    #[test]
    fn quaternions_from_users_are_renormalised_within_tolerance_only() {
        use crate::lie::Quaternion;
        let stored = Quaternion::<f64>::from_input(&[0.0, 0.0, 0.0, 1.0000005]).unwrap();
        assert_eq!(stored, vec![0.0, 0.0, 0.0, 1.0]);
        let error = Quaternion::<f64>::from_input(&[0.0, 0.0, 0.0, 1.01]).unwrap_err();
        assert!(error.message.contains("norm"), "{error}");
        let error =
            crate::lie::Se3::<f64>::from_input(&[0.0, 0.0, 0.0, 2.0, 1.0, 2.0, 3.0]).unwrap_err();
        assert_eq!(error.path, "rotation");
    }
}
