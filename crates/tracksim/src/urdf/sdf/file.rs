//! An SDFormat file read and parsed (roxmltree keeps every element's position), the context
//! every message is made in (the file, the element and its line), strict number lists, and
//! the choice of the robot's `<model>`.

use crate::error::SpecIssue;
use std::path::{Path, PathBuf};

/// Largest SDF file read, bytes (a world with its models is hundreds of kilobytes).
pub const MAX_SDF_BYTES: u64 = 16 << 20;

/// Where messages are made: the file, its document and the key they are filed under.
pub(super) struct Ctx<'a, 'input> {
    /// The SDF file.
    pub path: &'a Path,
    /// The parsed document.
    pub doc: &'a roxmltree::Document<'input>,
    /// The key prefix: `urdf` (the vehicle file's key) or `sdf` (a world read for terrain).
    pub key: &'static str,
}

/// An element of the document.
pub(super) type Node<'a, 'input> = roxmltree::Node<'a, 'input>;

impl<'a, 'input> Ctx<'a, 'input> {
    /// The file's name, for messages.
    pub fn file(&self) -> String {
        self.path
            .file_name()
            .map(|f| f.to_string_lossy().into_owned())
            .unwrap_or_default()
    }

    /// The line of `n` (1-based).
    pub fn line(&self, n: Node) -> u32 {
        self.doc.text_pos_at(n.range().start).row
    }

    /// `<tag name="NAME"> (FILE line N)`.
    pub fn at(&self, n: Node) -> String {
        let name = n
            .attribute("name")
            .map(|v| format!(" name=\"{}\"", crate::check::echoed(v)))
            .unwrap_or_default();
        format!(
            "<{}{name}> ({} line {})",
            n.tag_name().name(),
            self.file(),
            self.line(n)
        )
    }

    /// A problem with element `n`.
    pub fn issue(&self, n: Node, message: impl Into<String>) -> SpecIssue {
        SpecIssue::new(format!("{} {}", self.key, self.at(n)), message)
    }

    /// The folder of the file (relative URIs are relative to it).
    pub fn dir(&self) -> PathBuf {
        self.path.parent().unwrap_or(Path::new(".")).to_path_buf()
    }
}

/// The first child element of `n` called `tag`.
pub(super) fn child<'a, 'input>(n: Node<'a, 'input>, tag: &str) -> Option<Node<'a, 'input>> {
    n.children().find(|c| c.has_tag_name(tag))
}

/// The child elements of `n` called `tag`.
pub(super) fn children<'a, 'input>(
    n: Node<'a, 'input>,
    tag: &'static str,
) -> impl Iterator<Item = Node<'a, 'input>> {
    n.children().filter(move |c| c.has_tag_name(tag))
}

/// The trimmed text of element `n` ("" when empty).
pub(super) fn text<'a>(n: Node<'a, '_>) -> &'a str {
    n.text().map(str::trim).unwrap_or_default()
}

/// The numbers of element `n`: exactly `count` of them (any of `counts`), each finite.
pub(super) fn numbers(ctx: &Ctx, n: Node, counts: &[usize]) -> Result<Vec<f64>, SpecIssue> {
    let t = text(n);
    let mut out = Vec::new();
    for w in t.split_whitespace() {
        match w.parse::<f64>() {
            Ok(v) if v.is_finite() => out.push(v),
            Ok(_) => return Err(ctx.issue(n, format!("`{w}` is not a finite number"))),
            Err(_) => {
                return Err(ctx.issue(n, format!("`{}` is not a number", crate::check::echoed(w))));
            }
        }
    }
    if !counts.contains(&out.len()) {
        let want: Vec<String> = counts.iter().map(|c| c.to_string()).collect();
        return Err(ctx.issue(
            n,
            format!(
                "has {} numbers (`{}`); it takes {}",
                out.len(),
                crate::check::echoed(t),
                want.join(" or ")
            ),
        ));
    }
    Ok(out)
}

/// The one number of child `<tag>` of `n`, or `default` when there is no such child.
pub(super) fn number_of(ctx: &Ctx, n: Node, tag: &str, default: f64) -> Result<f64, SpecIssue> {
    match child(n, tag) {
        Some(c) => Ok(numbers(ctx, c, &[1])?[0]),
        None => Ok(default),
    }
}

/// `<static>` of a model: `true` or `1`.
pub(super) fn is_static(model: Node) -> bool {
    child(model, "static").is_some_and(|s| matches!(text(s), "1" | "true"))
}

/// The models a robot may be chosen from: `<model>` children of `<sdf>` and of its worlds.
pub(super) fn models<'a, 'input>(root: Node<'a, 'input>) -> Vec<Node<'a, 'input>> {
    let mut out: Vec<Node> = children(root, "model").collect();
    for w in children(root, "world") {
        out.extend(children(w, "model"));
    }
    out
}

/// Reads and parses the SDF file `path` (`key`: the key prefix of its problems).
/// Its nesting and element counts are checked before it is parsed (`urdf/limits.rs`).
pub(super) fn read_text(path: &Path, key: &str) -> Result<String, Vec<SpecIssue>> {
    let text = crate::files::read_text_bounded(path, MAX_SDF_BYTES).map_err(|e| {
        vec![SpecIssue::new(
            key,
            format!(
                "cannot read the SDF file: {e}; the path is relative to the vehicle file's folder"
            ),
        )]
    })?;
    super::super::limits::prescan_xml(path, &text, true)
        .map_err(|m| vec![SpecIssue::new(key, m)])?;
    Ok(text)
}

/// Parses `text` (the file `path`) as XML with an `<sdf>` root.
pub(super) fn parse<'input>(
    path: &Path,
    text: &'input str,
    key: &str,
) -> Result<roxmltree::Document<'input>, Vec<SpecIssue>> {
    let doc = roxmltree::Document::parse(text).map_err(|e| {
        vec![SpecIssue::new(
            key,
            format!("{} is not well-formed XML: {e}", path.display()),
        )]
    })?;
    if doc.root_element().tag_name().name() != "sdf" {
        return Err(vec![SpecIssue::new(
            key,
            format!(
                "{}: the root element is <{}>, an SDF file's is <sdf>",
                path.display(),
                doc.root_element().tag_name().name()
            ),
        )]);
    }
    Ok(doc)
}

/// The robot's `<model>`: the one named `wanted`, else the one model with a tracked-vehicle
/// plugin, else the only non-static model; otherwise a problem listing the models.
pub(super) fn choose_model<'a, 'input>(
    ctx: &Ctx<'a, 'input>,
    wanted: Option<&str>,
) -> Result<Node<'a, 'input>, SpecIssue> {
    let root = ctx.doc.root_element();
    let all = models(root);
    let names = |ms: &[Node]| -> String {
        ms.iter()
            .map(|m| {
                format!(
                    "\"{}\"",
                    crate::check::echoed(m.attribute("name").unwrap_or(""))
                )
            })
            .collect::<Vec<_>>()
            .join(", ")
    };
    let file = ctx.path.display();
    let includes = root
        .descendants()
        .filter(|n| n.has_tag_name("include"))
        .count();
    let include_note = if includes > 0 {
        format!(
            " ({includes} <include> element(s) are not read: expand them, e.g. `gz sdf -p {}`)",
            ctx.file()
        )
    } else {
        String::new()
    };
    if let Some(w) = wanted {
        return match all.iter().find(|m| m.attribute("name") == Some(w)) {
            Some(m) if is_static(*m) => Err(ctx.issue(
                *m,
                "is <static>: it cannot be a robot (static models are the world's terrain)",
            )),
            Some(m) => Ok(*m),
            None => Err(SpecIssue::new(
                "sdf_model",
                format!(
                    "{file} has no <model name=\"{}\">; its models are {}{include_note}",
                    crate::check::echoed(w),
                    if all.is_empty() {
                        "none".into()
                    } else {
                        names(&all)
                    }
                ),
            )),
        };
    }
    if all.is_empty() {
        return Err(SpecIssue::new(
            ctx.key,
            format!("{file} has no <model>{include_note}"),
        ));
    }
    let with_plugin: Vec<Node> = all
        .iter()
        .copied()
        .filter(|m| children(*m, "plugin").any(super::super::gazebo::is_tracked_vehicle))
        .collect();
    if let [one] = with_plugin.as_slice() {
        return Ok(*one);
    }
    let moving: Vec<Node> = all.iter().copied().filter(|m| !is_static(*m)).collect();
    match (with_plugin.as_slice(), moving.as_slice()) {
        ([], [one]) => Ok(*one),
        ([], []) => Err(SpecIssue::new(
            ctx.key,
            format!(
                "every <model> of {file} is static ({}): none can be the robot",
                names(&all)
            ),
        )),
        ([], many) | (many, _) => Err(SpecIssue::new(
            "sdf_model",
            format!(
                "{file} has {} models that could be the robot ({}): name one with \
                 `sdf_model = \"NAME\"` in the vehicle file",
                many.len(),
                names(many)
            ),
        )),
    }
}
