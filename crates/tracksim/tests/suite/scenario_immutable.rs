//! The compiled `Scenario` is immutable after compile (issue 39): outside `model/`, no code of
//! the library, the CLI or the Python bindings assigns to a field of a `Scenario`. A variation
//! of a file (another method, duration, solver order, a moved start, a run that does not stop
//! at its outcome) is written into the file's keys through `model::Overrides` before compiling,
//! so it is checked like the file's own.
//!
//! The check is syntactic (read with `syn`), per function:
//! - a variable is bound to a `Scenario` if it is a parameter (of a function or a closure) or a
//!   `let` typed `Scenario` (also `&mut Scenario`, `Arc<Scenario>`, ...), or a `let` whose
//!   value is a call or method call of a function of these sources returning a `Scenario`
//!   (`load_scenario_with(..)?`, `t.file_scenario()?`, `cases::load(..)`, ...) or another such
//!   variable (`sc.clone()`), through `?`, `.unwrap()`, `.expect(..)`, `.clone()` and `&`;
//! - an assignment (`=`, `+=`, ...) whose left side is a field, index or deref path rooted at
//!   such a variable (`sc.method = ..`, `sc.outcome.stop = ..`, `s.solver.order_salt = ..`) is
//!   a finding; so is a `&mut Scenario` in any signature.
//!
//! Its limits: it knows no types, so a `Scenario` reached through a struct field, a tuple, a
//! `for` loop over scenarios, a `match` arm or a closure's return value is not tracked; a
//! mutation through a method (`sc.commands.push(..)`, `std::mem::swap`) or `&mut sc.field`
//! handed to a function is not seen; shadowing is ignored (a name once bound to a `Scenario`
//! stays so for the rest of its function). Tests under `tests/` are not checked: they may
//! still vary a scenario by mutation.

use super::layers::rust_files;
use std::collections::BTreeSet;
use std::path::{Path, PathBuf};
use syn::visit::Visit;

/// Does `ty` name `Scenario` (itself, behind references, or as a generic argument)?
fn mentions_scenario(ty: &syn::Type) -> bool {
    match ty {
        syn::Type::Reference(r) => mentions_scenario(&r.elem),
        syn::Type::Paren(p) => mentions_scenario(&p.elem),
        syn::Type::Group(g) => mentions_scenario(&g.elem),
        syn::Type::Path(p) => p.path.segments.iter().any(|s| {
            s.ident == "Scenario"
                || match &s.arguments {
                    syn::PathArguments::AngleBracketed(a) => a.args.iter().any(|g| match g {
                        syn::GenericArgument::Type(t) => mentions_scenario(t),
                        _ => false,
                    }),
                    _ => false,
                }
        }),
        _ => false,
    }
}

/// Is `ty` a `&mut` reference to a `Scenario`?
fn is_mut_scenario_ref(ty: &syn::Type) -> bool {
    matches!(ty, syn::Type::Reference(r) if r.mutability.is_some() && mentions_scenario(&r.elem))
}

/// The names of every function of the files that returns a `Scenario` (or a `Result`,
/// `Option`, ... of one).
#[derive(Default)]
struct ScenarioFns(BTreeSet<String>);

impl ScenarioFns {
    fn add(&mut self, sig: &syn::Signature) {
        if let syn::ReturnType::Type(_, ty) = &sig.output
            && mentions_scenario(ty)
        {
            self.0.insert(sig.ident.to_string());
        }
    }
}

impl<'ast> Visit<'ast> for ScenarioFns {
    fn visit_signature(&mut self, sig: &'ast syn::Signature) {
        self.add(sig);
        syn::visit::visit_signature(self, sig);
    }
}

/// Finds the assignments to a `Scenario`'s fields in one file.
struct Finder<'a> {
    file: String,
    fns: &'a BTreeSet<String>,
    /// Names bound to a `Scenario` in the function being read.
    vars: BTreeSet<String>,
    found: Vec<String>,
}

impl Finder<'_> {
    /// Does `e` give a `Scenario` (see the module's rules)?
    fn is_scenario(&self, e: &syn::Expr) -> bool {
        match e {
            syn::Expr::Try(t) => self.is_scenario(&t.expr),
            syn::Expr::Paren(p) => self.is_scenario(&p.expr),
            syn::Expr::Reference(r) => self.is_scenario(&r.expr),
            syn::Expr::MethodCall(m) => {
                let name = m.method.to_string();
                if ["clone", "unwrap", "expect", "to_owned"].contains(&name.as_str()) {
                    self.is_scenario(&m.receiver)
                } else {
                    self.fns.contains(&name)
                }
            }
            syn::Expr::Call(c) => match &*c.func {
                syn::Expr::Path(p) => p
                    .path
                    .segments
                    .last()
                    .is_some_and(|s| self.fns.contains(&s.ident.to_string())),
                _ => false,
            },
            syn::Expr::Path(p) => p
                .path
                .get_ident()
                .is_some_and(|i| self.vars.contains(&i.to_string())),
            _ => false,
        }
    }

    /// The variable a place expression is rooted at, if it goes through at least one field,
    /// index or deref (`sc.a.b`, `sc.v[0]`, `*sc`).
    fn root(e: &syn::Expr, depth: usize) -> Option<String> {
        match e {
            syn::Expr::Field(f) => Self::root(&f.base, depth + 1),
            syn::Expr::Index(i) => Self::root(&i.expr, depth + 1),
            syn::Expr::Paren(p) => Self::root(&p.expr, depth),
            syn::Expr::Unary(u) if matches!(u.op, syn::UnOp::Deref(_)) => {
                Self::root(&u.expr, depth + 1)
            }
            syn::Expr::Path(p) if depth > 0 => p.path.get_ident().map(|i| i.to_string()),
            _ => None,
        }
    }

    fn check_place(&mut self, place: &syn::Expr) {
        if let Some(v) = Self::root(place, 0)
            && self.vars.contains(&v)
        {
            self.found.push(format!(
                "{}: `{} = ..` assigns to a field of the Scenario `{v}`",
                self.file,
                place_text(place)
            ));
        }
    }

    fn bind_pat(&mut self, pat: &syn::Pat, scenario: bool) {
        match pat {
            syn::Pat::Ident(i) if scenario => {
                self.vars.insert(i.ident.to_string());
            }
            syn::Pat::Type(t) => self.bind_pat(&t.pat, scenario || mentions_scenario(&t.ty)),
            _ => {}
        }
    }

    fn check_sig(&mut self, sig: &syn::Signature) {
        for input in &sig.inputs {
            if let syn::FnArg::Typed(t) = input {
                if is_mut_scenario_ref(&t.ty) {
                    self.found.push(format!(
                        "{}: `{}` takes a `&mut Scenario`",
                        self.file, sig.ident
                    ));
                }
                self.bind_pat(&t.pat, mentions_scenario(&t.ty));
            }
        }
    }
}

/// A place expression as text, for messages (`sc.outcome.stop`, `sc.v[..]`, `*sc`).
fn place_text(e: &syn::Expr) -> String {
    match e {
        syn::Expr::Field(f) => match &f.member {
            syn::Member::Named(i) => format!("{}.{i}", place_text(&f.base)),
            syn::Member::Unnamed(i) => format!("{}.{}", place_text(&f.base), i.index),
        },
        syn::Expr::Index(i) => format!("{}[..]", place_text(&i.expr)),
        syn::Expr::Paren(p) => place_text(&p.expr),
        syn::Expr::Unary(u) => format!("*{}", place_text(&u.expr)),
        syn::Expr::Path(p) => p.path.get_ident().map_or("..".into(), |i| i.to_string()),
        _ => "..".into(),
    }
}

impl<'ast> Visit<'ast> for Finder<'_> {
    fn visit_item_fn(&mut self, f: &'ast syn::ItemFn) {
        let outer = std::mem::take(&mut self.vars);
        self.check_sig(&f.sig);
        syn::visit::visit_item_fn(self, f);
        self.vars = outer;
    }

    fn visit_impl_item_fn(&mut self, f: &'ast syn::ImplItemFn) {
        let outer = std::mem::take(&mut self.vars);
        self.check_sig(&f.sig);
        syn::visit::visit_impl_item_fn(self, f);
        self.vars = outer;
    }

    fn visit_expr_closure(&mut self, c: &'ast syn::ExprClosure) {
        for p in &c.inputs {
            self.bind_pat(p, false);
        }
        syn::visit::visit_expr_closure(self, c);
    }

    fn visit_local(&mut self, l: &'ast syn::Local) {
        let scenario = l.init.as_ref().is_some_and(|i| self.is_scenario(&i.expr));
        self.bind_pat(&l.pat, scenario);
        syn::visit::visit_local(self, l);
    }

    fn visit_expr_assign(&mut self, a: &'ast syn::ExprAssign) {
        self.check_place(&a.left);
        syn::visit::visit_expr_assign(self, a);
    }

    fn visit_expr_binary(&mut self, b: &'ast syn::ExprBinary) {
        use syn::BinOp::*;
        if matches!(
            b.op,
            AddAssign(_)
                | SubAssign(_)
                | MulAssign(_)
                | DivAssign(_)
                | RemAssign(_)
                | BitXorAssign(_)
                | BitAndAssign(_)
                | BitOrAssign(_)
                | ShlAssign(_)
                | ShrAssign(_)
        ) {
            self.check_place(&b.left);
        }
        syn::visit::visit_expr_binary(self, b);
    }
}

/// The findings in `files` (name, source), with the `Scenario`-returning functions of `all`.
fn findings(files: &[(String, String)], all: &[(String, String)]) -> Vec<String> {
    let parse = |(name, text): &(String, String)| {
        syn::parse_file(text).unwrap_or_else(|e| panic!("{name}: {e}"))
    };
    let mut fns = ScenarioFns::default();
    for f in all {
        fns.visit_file(&parse(f));
    }
    let mut found = Vec::new();
    for f in files {
        let mut finder = Finder {
            file: f.0.clone(),
            fns: &fns.0,
            vars: BTreeSet::new(),
            found: Vec::new(),
        };
        finder.visit_file(&parse(f));
        found.extend(finder.found);
    }
    found
}

/// Every `.rs` file of the library's, the CLI's and the Python bindings' `src/`.
fn sources() -> Vec<PathBuf> {
    let crates = Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .expect("crates/")
        .to_path_buf();
    let mut files = Vec::new();
    for c in ["tracksim", "tracksim-cli", "tracksim-py"] {
        rust_files(&crates.join(c).join("src"), &mut files);
    }
    files.sort();
    files
}

#[test]
fn no_code_outside_model_assigns_to_a_compiled_scenario() {
    let model = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("src")
        .join("model");
    let read = |p: &PathBuf| (p.display().to_string(), std::fs::read_to_string(p).unwrap());
    let all: Vec<(String, String)> = sources().iter().map(read).collect();
    let outside: Vec<(String, String)> = sources()
        .iter()
        .filter(|p| !p.starts_with(&model))
        .map(read)
        .collect();
    assert!(outside.len() > 100, "only {} files read", outside.len());
    let found = findings(&outside, &all);
    assert!(
        found.is_empty(),
        "a compiled Scenario is changed outside model/ (write the change into the file's keys \
         through model::Overrides instead):\n{}",
        found.join("\n")
    );
}

#[test]
fn the_check_finds_the_assignments_it_states() {
    let lib = r#"
        pub fn load_scenario_with(p: &Path, o: &Overrides) -> Result<Scenario> { todo!() }
        impl ScenarioTemplate { pub fn file_scenario(&self) -> Result<Scenario> { todo!() } }
    "#;
    let user = r#"
        fn a(sc: &Scenario) { let mut s = sc.clone(); s.method = M; }
        fn b(p: &Path) { let mut sc = load_scenario_with(p, &o)?; sc.outcome.stop = false; }
        fn c(t: &T) { let mut s = t.file_scenario().unwrap(); s.solver.order_salt += 1; }
        fn d(sc: &mut Scenario) {}
        fn e(v: &mut Vehicle) { v.sensors = Vec::new(); let mut n = 1; n += 1; }
        fn f(sc: &Scenario) { let k = |s: &mut Stuff| s.x = 1; }
    "#;
    let files = vec![
        ("lib.rs".to_string(), lib.to_string()),
        ("user.rs".to_string(), user.to_string()),
    ];
    let found = findings(&files[1..], &files);
    let text = found.join("\n");
    assert_eq!(found.len(), 4, "{text}");
    for what in [
        "`s.method = ..` assigns to a field of the Scenario `s`",
        "`sc.outcome.stop = ..` assigns to a field of the Scenario `sc`",
        "`s.solver.order_salt = ..`",
        "`d` takes a `&mut Scenario`",
    ] {
        assert!(text.contains(what), "{what} not found in:\n{text}");
    }
}

/// The override keys added for the benchmark and the ensembles are written into the file's
/// keys and checked like them, their problems naming the key and what overrode it.
#[test]
fn the_new_overrides_are_checked_like_the_files_keys() {
    let f = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenarios/packbot_flat.toml");
    let load = |o: tracksim::Overrides| tracksim::load_scenario_with(&f, &o);
    let plain = load(tracksim::Overrides::default()).unwrap();
    let o = tracksim::Overrides {
        stop_at_outcome: Some(false),
        order_salt: Some(3),
        start_offset: Some(tracksim::model::StartOffset {
            x_m: 0.25,
            y_m: -0.5,
            yaw_deg: 90.0,
        }),
        ..Default::default()
    };
    let sc = load(o).unwrap();
    assert!(plain.outcome.stop && !sc.outcome.stop);
    assert_eq!(sc.solver.order_salt, 3);
    assert_eq!(
        sc.start_xy,
        (plain.start_xy.0 + 0.25, plain.start_xy.1 - 0.5)
    );
    assert_eq!(sc.start_yaw, 90f64.to_radians());
    assert_eq!(
        sc.overridden,
        [
            "outcome.stop",
            "simulation.order_salt",
            "vehicle.x_m",
            "vehicle.y_m",
            "vehicle.yaw_deg"
        ]
    );
    let e = load(tracksim::Overrides {
        order_salt: Some(100_000),
        ..Default::default()
    })
    .unwrap_err()
    .to_string();
    assert!(
        e.contains("simulation.order_salt (overridden: an ensemble member's solver order)")
            && e.contains("must be between 0 and 1024"),
        "{e}"
    );
}
