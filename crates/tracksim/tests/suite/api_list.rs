//! docs/API.md lists the stepping API in one place (issue 39): every public method of
//! `Simulation` (in whichever file of `world/` it is written) is listed there, and nothing
//! listed is gone.

use crate::common::root;
use std::collections::BTreeSet;

/// The `.rs` files under `dir`, sub-folders included.
fn rust_files(dir: &std::path::Path) -> Vec<std::path::PathBuf> {
    let mut out = Vec::new();
    for e in std::fs::read_dir(dir).unwrap() {
        let p = e.unwrap().path();
        if p.is_dir() {
            out.extend(rust_files(&p));
        } else if p.extension().is_some_and(|x| x == "rs") {
            out.push(p);
        }
    }
    out
}

/// The public methods of `impl Simulation` blocks in `src/world/` (sub-folders included),
/// read from the sources.
fn simulation_methods() -> BTreeSet<String> {
    let mut out = BTreeSet::new();
    for p in rust_files(&root().join("crates/tracksim/src/world")) {
        let ast = syn::parse_file(&std::fs::read_to_string(&p).unwrap()).unwrap();
        for item in ast.items {
            let syn::Item::Impl(i) = item else { continue };
            let syn::Type::Path(t) = &*i.self_ty else {
                continue;
            };
            if i.trait_.is_some() || !t.path.is_ident("Simulation") {
                continue;
            }
            for it in i.items {
                if let syn::ImplItem::Fn(f) = it
                    && matches!(f.vis, syn::Visibility::Public(_))
                {
                    out.insert(f.sig.ident.to_string());
                }
            }
        }
    }
    out
}

#[test]
fn every_public_simulation_method_is_listed_in_api_md() {
    let doc = std::fs::read_to_string(root().join("docs/API.md")).unwrap();
    let listed: BTreeSet<String> = doc
        .match_indices("`Simulation::")
        .map(|(i, _)| {
            doc[i + 13..]
                .chars()
                .take_while(|c| c.is_alphanumeric() || *c == '_')
                .collect()
        })
        .collect();
    let methods = simulation_methods();
    assert!(methods.len() > 50, "found {} methods", methods.len());
    let unlisted: Vec<_> = methods.difference(&listed).collect();
    let gone: Vec<_> = listed.difference(&methods).collect();
    assert!(
        unlisted.is_empty() && gone.is_empty(),
        "docs/API.md: not listed {unlisted:?}, listed but gone {gone:?}"
    );
}
