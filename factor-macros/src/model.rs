//! The derive input parsed into a small model, with every misuse reported as
//! a spanned compile error. Emission ([`crate::emit`]) never fails.

use syn::{
    Attribute, Data, DeriveInput, Fields, GenericArgument, GenericParam, Generics, Ident, LitInt,
    Path, PathArguments, Type, TypeParamBound, Visibility, WherePredicate,
};

use proc_macro2::{Group, Span, TokenStream, TokenTree};
use quote::ToTokens;
use syn::spanned::Spanned;

use crate::attrs::{self, FactorAttr, HostAttr, Side};
use crate::errors;
use crate::naming;

/// A validated `#[derive(Factor)]` input.
pub struct FactorModel {
    /// The struct's visibility, given to the generated linearization struct.
    pub vis: Visibility,
    /// The struct's name.
    pub ident: Ident,
    /// The struct's generics: exactly one type parameter.
    pub generics: Generics,
    /// That type parameter, the scalar.
    pub scalar: Ident,
    /// `residual = path`.
    pub residual: Path,
    /// `dim = integer`, at least 1.
    pub dim: LitInt,
    /// `validate = path`, if given.
    pub validate: Option<Path>,
    /// `name = "..."`, or the snake case of the struct's name.
    pub name: String,
    /// `kernel = path`, if given: the generated kernel function.
    pub kernel: Option<Path>,
    /// `regenerate = "command"`, if given: how to rewrite a stale kernel.
    pub regenerate: Option<String>,
    /// `hosts(...)`: the host charts the kernel crate has kernels for.
    pub hosts: Vec<HostAttr>,
    /// The first paragraph of the struct's documentation, on one line.
    pub doc: String,
    /// Every field in declaration order.
    pub fields: Vec<Field>,
}

/// A field of the factor struct.
pub struct Field {
    /// The field's name.
    pub ident: Ident,
    /// The field's type as written (over the scalar parameter), every token
    /// spanned at its first ([`spanned_at_first_token`]).
    pub ty: Type,
    /// Constant or variable.
    pub kind: FieldKind,
    /// The first paragraph of the field's documentation, on one line.
    pub doc: String,
}

/// What a field is to the factor.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum FieldKind {
    /// No attribute: fixed data, lifted to the scalar but never perturbed.
    Constant,
    /// `#[variable(...)]`: a manifold the residual is differentiated on.
    Variable(Side),
}

impl FactorModel {
    /// Parses and validates the input, reporting every error found.
    pub fn from_input(input: &DeriveInput) -> syn::Result<Self> {
        let scalar = scalar_param(&input.generics, &input.ident);
        let attr =
            FactorAttr::parse(&input.attrs).and_then(|attr| required_keys(attr, &input.ident));
        let fields = parse_fields(input);
        let misplaced = errors::check(misplaced_attrs(input));
        let (((scalar, (residual, dim, validate, name, kernel, regenerate, hosts)), fields), ()) =
            errors::join(errors::join(errors::join(scalar, attr), fields), misplaced)?;
        Ok(FactorModel {
            vis: input.vis.clone(),
            ident: input.ident.clone(),
            generics: input.generics.clone(),
            scalar,
            residual,
            dim,
            validate,
            name: name.unwrap_or_else(|| naming::snake_case(&input.ident.to_string())),
            kernel,
            regenerate,
            hosts,
            doc: first_paragraph(&input.attrs),
            fields,
        })
    }

    /// The variables with their perturbation sides, in declaration order.
    pub fn variables(&self) -> impl Iterator<Item = (&Field, Side)> {
        self.fields.iter().filter_map(|field| match field.kind {
            FieldKind::Variable(side) => Some((field, side)),
            FieldKind::Constant => None,
        })
    }

    /// `FooLinearization`.
    pub fn linearization_ident(&self) -> Ident {
        quote::format_ident!("{}Linearization", self.ident)
    }
}

/// The residual, dimension, validation function, name, kernel, its
/// regeneration command and its hosts, once both required keys are known to
/// be present.
type Keys = (
    Path,
    LitInt,
    Option<Path>,
    Option<String>,
    Option<Path>,
    Option<String>,
    Vec<HostAttr>,
);

fn required_keys(attr: FactorAttr, ident: &Ident) -> syn::Result<Keys> {
    let Some(first) = &attr.first else {
        return Err(syn::Error::new(
            ident.span(),
            "missing `#[factor(residual = <function>, dim = <integer>)]` on the factor struct",
        ));
    };
    let residual = attr.residual.ok_or_else(|| {
        syn::Error::new_spanned(
            first,
            "missing `residual = <function>` in `#[factor(...)]`: the generic residual \
             `fn<S: Scalar>(&Factor<S>) -> SVector<S, DIM>`",
        )
    });
    let dim = attr.dim.ok_or_else(|| {
        syn::Error::new_spanned(
            first,
            "missing `dim = <integer>` in `#[factor(...)]`: the residual dimension",
        )
    });
    let regenerate = match (&attr.regenerate, &attr.kernel) {
        (Some(command), None) => Err(syn::Error::new(
            command.span(),
            "`regenerate` names the command that rewrites the generated kernel: it needs \
             `kernel = <path>`",
        )),
        _ => Ok(()),
    };
    let hosts = match (&attr.hosts, &attr.kernel) {
        (Some(hosts), None) => Err(syn::Error::new(
            hosts[0].name.span(),
            "`hosts` names the host charts the generated kernel crate has kernels for: it \
             needs `kernel = <path>`",
        )),
        _ => Ok(()),
    };
    let (((residual, dim), ()), ()) =
        errors::join(errors::join(errors::join(residual, dim), regenerate), hosts)?;
    Ok((
        residual,
        dim,
        attr.validate,
        attr.name.map(|name| name.value()),
        attr.kernel,
        attr.regenerate.map(|command| command.value()),
        attr.hosts.unwrap_or_default(),
    ))
}

/// The single type parameter; lifetimes and const parameters are rejected,
/// and so is any bound on it but `Scalar` ([`extra_bounds`]).
fn scalar_param(generics: &Generics, ident: &Ident) -> syn::Result<Ident> {
    let message = "a factor struct has exactly one type parameter, the scalar, \
                   and no lifetimes or const parameters: `struct Factor<S: Scalar = f64>`";
    let mut params = generics.params.iter();
    match (params.next(), params.next()) {
        (Some(GenericParam::Type(param)), None) => {
            errors::check(extra_bounds(generics, &param.ident))?;
            Ok(param.ident.clone())
        }
        (None, _) => Err(syn::Error::new(ident.span(), message)),
        _ => Err(syn::Error::new_spanned(&generics.params, message)),
    }
}

/// Every bound on the scalar `scalar` but `Scalar` (and those it implies),
/// in its declaration or in the `where` clause. The factor is instantiated at `f64`, dual numbers and
/// a symbolic scalar, which share `Scalar` and nothing more; a comparison
/// bound (rustc's hint for `a < b` in the residual) gets `select_lt`.
fn extra_bounds(generics: &Generics, scalar: &Ident) -> Vec<syn::Error> {
    let declared = generics
        .type_params()
        .filter(|param| &param.ident == scalar)
        .flat_map(|param| &param.bounds);
    let in_where = generics
        .where_clause
        .iter()
        .flat_map(|clause| &clause.predicates)
        .filter_map(|predicate| match predicate {
            WherePredicate::Type(bound) if is_ident(&bound.bounded_ty, scalar) => {
                Some(&bound.bounds)
            }
            _ => None,
        })
        .flatten();
    declared
        .chain(in_where)
        .filter_map(|bound| {
            let TypeParamBound::Trait(bound) = bound else {
                return None; // `'static`, which `Scalar` implies
            };
            let name = bound.path.segments.last()?.ident.to_string();
            match name.as_str() {
                // `Scalar` and bounds it implies.
                "Scalar" | "Copy" | "Clone" | "Debug" | "PartialEq" | "Send" | "Sync" => None,
                "PartialOrd" | "Ord" | "Eq" => Some(syn::Error::new_spanned(
                    bound,
                    format!(
                        "the scalar `{scalar}` takes the bound `Scalar` alone, not `{name}`: the \
                         residual runs on dual numbers and is traced over a symbolic scalar, \
                         which cannot answer `<`; branch with \
                         `Scalar::select_lt(a, b, if_less, otherwise)` (`if a < b {{ if_less }} \
                         else {{ otherwise }}`, both arms evaluated) and take `{name}` off the \
                         residual function's `{scalar}` too"
                    ),
                )),
                _ => Some(syn::Error::new_spanned(
                    bound,
                    format!(
                        "the scalar `{scalar}` takes the bound `Scalar` alone, not `{name}`: the \
                         factor is instantiated at `f64`, dual numbers and a symbolic scalar, \
                         which share `Scalar` (its arithmetic, `sqrt`, `sin`, `cos`, `atan2`, \
                         `exp`, `ln`, `acos`, `asin`, `atan` and `select_lt`) and nothing more"
                    ),
                )),
            }
        })
        .collect()
}

/// Whether `ty` is the plain identifier `ident`.
fn is_ident(ty: &Type, ident: &Ident) -> bool {
    matches!(ty, Type::Path(path) if path.qself.is_none() && path.path.is_ident(ident))
}

/// The first `f64` or `f32` written in a field's type (`f64`, `[f64; 3]`,
/// `Vector3<f64>`), which should be the scalar parameter: constants are
/// lifted to dual numbers and traced like variables.
fn float_in(ty: &Type) -> Option<&Ident> {
    match ty {
        Type::Path(path) => {
            let qself = path.qself.as_ref().and_then(|q| float_in(&q.ty));
            qself.or_else(|| {
                path.path.segments.iter().find_map(|segment| {
                    if segment.ident == "f64" || segment.ident == "f32" {
                        return Some(&segment.ident);
                    }
                    match &segment.arguments {
                        PathArguments::AngleBracketed(args) => {
                            args.args.iter().find_map(|arg| match arg {
                                GenericArgument::Type(ty) => float_in(ty),
                                _ => None,
                            })
                        }
                        _ => None,
                    }
                })
            })
        }
        Type::Array(array) => float_in(&array.elem),
        Type::Slice(slice) => float_in(&slice.elem),
        Type::Reference(reference) => float_in(&reference.elem),
        Type::Paren(paren) => float_in(&paren.elem),
        Type::Group(group) => float_in(&group.elem),
        Type::Tuple(tuple) => tuple.elems.iter().find_map(float_in),
        _ => None,
    }
}

fn parse_fields(input: &DeriveInput) -> syn::Result<Vec<Field>> {
    let named = match &input.data {
        Data::Struct(data) => match &data.fields {
            Fields::Named(named) => named,
            Fields::Unnamed(unnamed) => {
                return Err(syn::Error::new_spanned(
                    unnamed,
                    "`#[derive(Factor)]` needs named fields; a tuple struct has none",
                ));
            }
            Fields::Unit => {
                return Err(syn::Error::new(
                    input.ident.span(),
                    "`#[derive(Factor)]` needs named fields: at least one `#[variable]`",
                ));
            }
        },
        Data::Enum(data) => {
            return Err(syn::Error::new(
                data.enum_token.span,
                "`#[derive(Factor)]` applies to structs only, not enums",
            ));
        }
        Data::Union(data) => {
            return Err(syn::Error::new(
                data.union_token.span,
                "`#[derive(Factor)]` applies to structs only, not unions",
            ));
        }
    };
    let fields = errors::collect(named.named.iter().map(|field| {
        let ident = field
            .ident
            .clone()
            .ok_or_else(|| syn::Error::new_spanned(field, "unnamed field"))?;
        let kind = match attrs::variable_side(&field.attrs)? {
            Some(side) => FieldKind::Variable(side),
            None => FieldKind::Constant,
        };
        if let Some(float) = float_in(&field.ty) {
            let scalar = scalar_name(&input.generics);
            return Err(syn::Error::new(
                float.span(),
                format!(
                    "`{ident}` is written over `{float}`; a factor's fields are written over its \
                     scalar `{scalar}` (`{scalar}`, `[{scalar}; 3]`, `Vector3<{scalar}>`), \
                     constants too: the factor is lifted to dual numbers and traced over a \
                     symbolic scalar, every field with it. Write `{scalar}` here (a \
                     `{factor}<f64>` still holds an `f64` there)",
                    factor = input.ident,
                ),
            ));
        }
        if kind != FieldKind::Constant && ident == "residual" {
            return Err(syn::Error::new(
                ident.span(),
                format!(
                    "a variable cannot be named `residual`: `{}Linearization` has a `residual` \
                     field beside one Jacobian field per variable",
                    input.ident
                ),
            ));
        }
        Ok(Field {
            ident,
            ty: spanned_at_first_token(&field.ty),
            kind,
            doc: first_paragraph(&field.attrs),
        })
    }))?;
    if fields.iter().all(|field| field.kind == FieldKind::Constant) {
        return Err(syn::Error::new(
            input.ident.span(),
            "a factor needs at least one variable: mark the fields the residual is \
             differentiated on with `#[variable]`, `#[variable(left)]` or `#[variable(right)]`",
        ));
    }
    Ok(fields)
}

/// `ty` with every token spanned at its first. The derive spans each use
/// of a field type's traits at the type (see `emit`); rustc reports a
/// missing trait at a path's self type with the type's span, and at a call
/// returning one of the trait's associated types with the call's span, from
/// its first token to its last, which the derive can only span at one token
/// (joining spans is unstable). With the type itself spanned at one token,
/// both reports have the same span and text, and rustc prints one.
fn spanned_at_first_token(ty: &Type) -> Type {
    fn respan(tokens: TokenStream, span: Span) -> TokenStream {
        tokens
            .into_iter()
            .map(|mut token| {
                if let TokenTree::Group(group) = &token {
                    let mut inner = Group::new(group.delimiter(), respan(group.stream(), span));
                    inner.set_span(span);
                    token = TokenTree::Group(inner);
                } else {
                    token.set_span(span);
                }
                token
            })
            .collect()
    }
    let span = ty.span();
    syn::parse2(respan(ty.to_token_stream(), span)).expect("a type re-spanned is a type")
}

/// The scalar parameter's name as written, for messages (`S` when the
/// struct has none).
fn scalar_name(generics: &Generics) -> String {
    generics
        .type_params()
        .next()
        .map_or_else(|| "S".to_owned(), |param| param.ident.to_string())
}

/// `#[variable]` on the struct or `#[factor]` on a field.
fn misplaced_attrs(input: &DeriveInput) -> Vec<syn::Error> {
    let on_struct = input
        .attrs
        .iter()
        .filter(|attr| attr.path().is_ident("variable"))
        .map(|attr| {
            syn::Error::new_spanned(attr, "`#[variable]` belongs on a field, not on the struct")
        });
    let field_attrs: Vec<&Attribute> = match &input.data {
        Data::Struct(data) => data.fields.iter().flat_map(|field| &field.attrs).collect(),
        Data::Enum(_) | Data::Union(_) => Vec::new(),
    };
    let on_field = field_attrs
        .into_iter()
        .filter(|attr| attr.path().is_ident("factor"))
        .map(|attr| {
            syn::Error::new_spanned(
                attr,
                "`#[factor(...)]` belongs on the struct, not on a field",
            )
        });
    on_struct.chain(on_field).collect()
}

/// The first paragraph of the `///` documentation in `attrs`, its lines
/// trimmed and joined by spaces (empty without documentation).
fn first_paragraph(attrs: &[Attribute]) -> String {
    let mut words = Vec::new();
    for attr in attrs.iter().filter(|attr| attr.path().is_ident("doc")) {
        let syn::Meta::NameValue(meta) = &attr.meta else {
            continue;
        };
        let syn::Expr::Lit(syn::ExprLit {
            lit: syn::Lit::Str(text),
            ..
        }) = &meta.value
        else {
            continue;
        };
        let line = text.value();
        let line = line.trim();
        if line.is_empty() {
            if words.is_empty() {
                continue;
            }
            break;
        }
        words.push(line.to_owned());
    }
    words.join(" ")
}
