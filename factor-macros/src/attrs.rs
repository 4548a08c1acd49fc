//! The helper attributes: `#[factor(...)]` on the struct and
//! `#[variable]` / `#[variable(left|right)]` on a field.

use syn::meta::ParseNestedMeta;
use syn::{Attribute, LitInt, LitStr, Meta, Path};

use crate::errors;

/// The keys of every `#[factor(...)]` attribute of the struct, merged.
#[derive(Default)]
pub struct FactorAttr {
    /// `residual = path`.
    pub residual: Option<Path>,
    /// `dim = integer`, checked to be at least 1.
    pub dim: Option<LitInt>,
    /// `validate = path`.
    pub validate: Option<Path>,
    /// `name = "..."`.
    pub name: Option<LitStr>,
    /// `kernel = path`: the generated kernel function.
    pub kernel: Option<Path>,
    /// `regenerate = "command"`: how to rewrite the kernel when it is stale.
    pub regenerate: Option<LitStr>,
    /// `hosts(apex, name = path::Host)`: the host charts the kernel crate
    /// has kernels for.
    pub hosts: Option<Vec<HostAttr>>,
    /// The first `#[factor]` attribute, for errors about a missing key.
    pub first: Option<Attribute>,
}

impl FactorAttr {
    /// Parses every `#[factor(...)]` attribute; a key may appear once overall.
    pub fn parse(attrs: &[Attribute]) -> syn::Result<Self> {
        let mut out = FactorAttr::default();
        let results = attrs
            .iter()
            .filter(|attr| attr.path().is_ident("factor"))
            .map(|attr| {
                out.first.get_or_insert_with(|| attr.clone());
                attr.parse_nested_meta(|meta| out.parse_key(&meta))
            })
            .collect::<Vec<_>>();
        errors::collect(results)?;
        Ok(out)
    }

    fn parse_key(&mut self, meta: &ParseNestedMeta) -> syn::Result<()> {
        let key = meta
            .path
            .get_ident()
            .map(ToString::to_string)
            .unwrap_or_default();
        match key.as_str() {
            "residual" => set_once(&mut self.residual, meta, meta.value()?.parse()?),
            "validate" => set_once(&mut self.validate, meta, meta.value()?.parse()?),
            "kernel" => set_once(&mut self.kernel, meta, meta.value()?.parse()?),
            "regenerate" => set_once(&mut self.regenerate, meta, meta.value()?.parse()?),
            "hosts" => {
                let hosts = parse_hosts(meta)?;
                set_once(&mut self.hosts, meta, hosts)
            }
            "name" => {
                let name: LitStr = meta.value()?.parse()?;
                if name.value().is_empty() {
                    return Err(syn::Error::new(name.span(), "the factor's `name` cannot be empty"));
                }
                set_once(&mut self.name, meta, name)
            }
            "dim" => {
                let dim: LitInt = meta.value()?.parse()?;
                if dim.base10_parse::<usize>()? == 0 {
                    return Err(syn::Error::new(
                        dim.span(),
                        "`dim` is the residual dimension and must be at least 1",
                    ));
                }
                set_once(&mut self.dim, meta, dim)
            }
            _ => Err(meta.error(format!(
                "unknown key `{}` in `#[factor(...)]`; expected `residual`, `dim`, `validate`, `name`, `kernel`, `regenerate` or `hosts`",
                path_text(&meta.path)
            ))),
        }
    }
}

/// A host chart with a generated kernel: `apex` (apex-solver,
/// `::factor_core::host::Apex`) or `name = path::ToHost` for a host of
/// one's own. The kernel of host `name` is `<kernel>_<name>`.
pub struct HostAttr {
    /// The host's name, the suffix of its kernel's name.
    pub name: syn::Ident,
    /// The host type.
    pub host: Path,
}

/// `hosts(apex, mine = my_crate::MyHost)`: at least one, each once.
fn parse_hosts(meta: &ParseNestedMeta) -> syn::Result<Vec<HostAttr>> {
    let mut hosts: Vec<HostAttr> = Vec::new();
    meta.parse_nested_meta(|host| {
        let Some(name) = host.path.get_ident().cloned() else {
            return Err(host.error("a host is named by one identifier: `apex` or `name = path`"));
        };
        let path = if host.input.peek(syn::Token![=]) {
            host.value()?.parse()?
        } else if name == "apex" {
            syn::parse_quote!(::factor_core::host::Apex)
        } else {
            return Err(host.error(format!(
                "unknown host `{name}`: the built-in host is `apex`; name a host of your own \
                 with `{name} = path::ToHostType`"
            )));
        };
        if hosts.iter().any(|h| h.name == name) {
            return Err(host.error(format!("duplicate host `{name}` in `hosts(...)`")));
        }
        hosts.push(HostAttr { name, host: path });
        Ok(())
    })?;
    if hosts.is_empty() {
        return Err(meta.error("`hosts(...)` names at least one host: `hosts(apex)`"));
    }
    Ok(hosts)
}

/// Stores `value` unless the key was already given.
fn set_once<T>(slot: &mut Option<T>, meta: &ParseNestedMeta, value: T) -> syn::Result<()> {
    if slot.is_some() {
        return Err(meta.error(format!(
            "duplicate `{}` in `#[factor(...)]`",
            path_text(&meta.path)
        )));
    }
    *slot = Some(value);
    Ok(())
}

fn path_text(path: &Path) -> String {
    quote::quote!(#path).to_string().replace(' ', "")
}

/// Side of a variable's perturbation, as written in `#[variable(...)]`.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum Side {
    /// `x ← Exp(δ) · x`; also the default of a bare `#[variable]`.
    Left,
    /// `x ← x · Exp(δ)`.
    Right,
}

impl Side {
    /// `"left"` or `"right"`, for generated documentation.
    pub fn as_str(self) -> &'static str {
        match self {
            Side::Left => "left",
            Side::Right => "right",
        }
    }
}

/// The perturbation side if the field has a `#[variable]` attribute.
pub fn variable_side(attrs: &[Attribute]) -> syn::Result<Option<Side>> {
    let mut variable_attrs = attrs.iter().filter(|attr| attr.path().is_ident("variable"));
    let Some(first) = variable_attrs.next() else {
        return Ok(None);
    };
    let side = parse_side(first);
    let duplicates = variable_attrs.map(|attr| {
        Err(syn::Error::new_spanned(
            attr,
            "duplicate `#[variable]` attribute; a field is marked as a variable once",
        ))
    });
    let sides = errors::collect(std::iter::once(side).chain(duplicates))?;
    Ok(sides.into_iter().next())
}

fn parse_side(attr: &Attribute) -> syn::Result<Side> {
    match &attr.meta {
        Meta::Path(_) => Ok(Side::Left),
        Meta::NameValue(_) => Err(syn::Error::new_spanned(
            attr,
            "expected `#[variable]`, `#[variable(left)]` or `#[variable(right)]`",
        )),
        Meta::List(_) => {
            let mut side = None;
            attr.parse_nested_meta(|meta| {
                let parsed = if meta.path.is_ident("left") {
                    Side::Left
                } else if meta.path.is_ident("right") {
                    Side::Right
                } else {
                    return Err(meta.error(format!(
                        "unknown perturbation side `{}`; expected `left` or `right`",
                        path_text(&meta.path)
                    )));
                };
                if side.replace(parsed).is_some() {
                    return Err(
                        meta.error("a variable has one perturbation side: `left` or `right`")
                    );
                }
                Ok(())
            })?;
            Ok(side.unwrap_or(Side::Left))
        }
    }
}
