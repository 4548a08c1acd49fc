//! Combining errors, so that one compilation reports every misuse of the
//! derive at once instead of the first one only.

/// Both values, or the errors of every part that failed.
pub fn join<A, B>(a: syn::Result<A>, b: syn::Result<B>) -> syn::Result<(A, B)> {
    match (a, b) {
        (Ok(a), Ok(b)) => Ok((a, b)),
        (Err(mut first), Err(second)) => {
            first.combine(second);
            Err(first)
        }
        (Err(error), Ok(_)) | (Ok(_), Err(error)) => Err(error),
    }
}

/// All values in order, or the errors of every item that failed.
pub fn collect<T>(items: impl IntoIterator<Item = syn::Result<T>>) -> syn::Result<Vec<T>> {
    let mut values = Vec::new();
    let mut errors: Option<syn::Error> = None;
    for item in items {
        match (item, &mut errors) {
            (Ok(value), _) => values.push(value),
            (Err(error), Some(first)) => first.combine(error),
            (Err(error), None) => errors = Some(error),
        }
    }
    errors.map_or(Ok(values), Err)
}

/// `Ok(())`, or every error of the list combined.
pub fn check(errors: Vec<syn::Error>) -> syn::Result<()> {
    collect(errors.into_iter().map(Err::<(), _>)).map(drop)
}
