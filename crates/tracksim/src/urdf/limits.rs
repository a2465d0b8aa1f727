//! The size bounds of a robot file and its meshes (issue 45), checked before any parser that
//! allocates or recurses is given the text: XML nesting depth and element counts (a streaming,
//! non-recursive pre-scan with quick-xml), and a COLLADA file's declared `count`s against the
//! data they announce. The magnitude bounds of the numbers are in `numbers.rs`; file sizes are
//! [`super::MAX_URDF_BYTES`] and [`super::MAX_ROBOT_MESH_BYTES`].
//!
//! Why these numbers: the recursive readers behind roxmltree's users (urdf-rs through serde,
//! mesh-loader's COLLADA scene graph) take a stack frame or more per level; 100,000 levels
//! overflowed the 8 MiB main stack. A robot description is shallow (gz-sim's worlds reach 10
//! levels: `sdf/world/model/link/collision/surface/friction/ode/mu`, nested models a few
//! more), so [`MAX_XML_DEPTH`] = 64 is six times the deepest real file and a few hundred KiB
//! of stack at most. The largest real robots tracksim imports have 39 links and 1,500
//! elements (gz-sim's `track_drive.sdf`); [`MAX_LINKS`] = 1,000 links and
//! [`MAX_XML_ELEMENTS`] = 100,000 elements keep the tree walk (quadratic in the links) and the
//! memory of 100,000 links (4.1 GB measured) out of reach.

use std::path::Path;

/// Deepest element nesting read in a URDF, SDF or COLLADA file (the root element is depth 1).
pub const MAX_XML_DEPTH: usize = 64;
/// Most elements in a URDF, SDF or COLLADA file.
pub const MAX_XML_ELEMENTS: usize = 100_000;
/// Most `<link name>` elements in a URDF or SDF file (all models, `<gazebo>` blocks included).
pub const MAX_LINKS: usize = 1_000;
/// Most `<joint name>` elements in a URDF or SDF file.
pub const MAX_JOINTS: usize = 1_000;
/// Most `<collision>` elements in a URDF or SDF file.
pub const MAX_COLLISIONS: usize = 10_000;

/// The file's name for messages.
fn name(path: &Path) -> String {
    path.file_name()
        .map(|f| f.to_string_lossy().into_owned())
        .unwrap_or_else(|| path.display().to_string())
}

/// Checks the nesting depth and element counts of the XML `text` (the file `path`) with a
/// streaming reader (no tree, no recursion), before a tree parser is given it. `robot`: also
/// counts `<link>`, `<joint>` and `<collision>` against their limits (a URDF or SDF file; not
/// a COLLADA mesh).
pub(crate) fn prescan_xml(path: &Path, text: &str, robot: bool) -> Result<(), String> {
    use quick_xml::events::Event;
    let file = name(path);
    let mut reader = quick_xml::Reader::from_str(text);
    let (mut depth, mut elements) = (0usize, 0usize);
    let (mut links, mut joints, mut collisions) = (0usize, 0usize, 0usize);
    loop {
        let event = reader.read_event().map_err(|e| {
            format!(
                "{file} is not well-formed XML (at byte {}): {}",
                reader.error_position(),
                crate::check::shorten(&e.to_string())
            )
        })?;
        let (start, open) = match &event {
            Event::Start(s) => (s, true),
            Event::Empty(s) => (s, false),
            Event::End(_) => {
                depth = depth.saturating_sub(1);
                continue;
            }
            Event::Eof => break,
            _ => continue,
        };
        elements += 1;
        let here = depth + 1;
        if here > MAX_XML_DEPTH {
            return Err(format!(
                "{file}: elements nested {here} deep at byte {}, more than the {MAX_XML_DEPTH} \
                 levels tracksim reads (a robot file is about 10 deep); remove the nesting",
                reader.buffer_position()
            ));
        }
        if open {
            depth = here;
        }
        if elements > MAX_XML_ELEMENTS {
            return Err(format!(
                "{file}: more than {MAX_XML_ELEMENTS} elements; a robot or mesh description has \
                 a few thousand: remove what is repeated"
            ));
        }
        // A robot's links and joints have a name (a plugin's `<link>NAME</link>` is a
        // reference, not a link).
        let named = || {
            start
                .attributes()
                .flatten()
                .any(|a| a.key.as_ref() == b"name")
        };
        if robot {
            let (count, limit, tag) = match start.local_name().as_ref() {
                b"link" | b"joint" if !named() => continue,
                b"link" => (&mut links, MAX_LINKS, "link"),
                b"joint" => (&mut joints, MAX_JOINTS, "joint"),
                b"collision" => (&mut collisions, MAX_COLLISIONS, "collision"),
                _ => continue,
            };
            *count += 1;
            if *count > limit {
                return Err(format!(
                    "{file}: more than {limit} <{tag}> elements; tracksim imports a robot of at \
                     most {limit} (a tracked robot has tens): merge links with fixed joints \
                     or split the file"
                ));
            }
        }
    }
    Ok(())
}

/// Number of whitespace-separated values in `node`'s text.
fn tokens(node: roxmltree::Node) -> u64 {
    node.text()
        .map_or(0, |t| t.split_ascii_whitespace().count() as u64)
}

/// Checks a COLLADA file's declared counts against its data before mesh-loader, which
/// reserves memory for a declared `count` before reading the values (a `float_array
/// count="4294967295"` aborted on allocation): every array's `count` must be the number of
/// values it holds, and the indices a primitive's `count` announces (`<triangles>`: 3 per
/// triangle per input offset; `<polylist>`: its `<vcount>` sum per offset) must be in its
/// `<p>` (mesh-loader reserves them first). Nesting and element counts are
/// checked first ([`prescan_xml`]).
pub(crate) fn check_collada(path: &Path, bytes: &[u8]) -> Result<(), String> {
    let file = name(path);
    let text = std::str::from_utf8(bytes)
        .map_err(|e| format!("{file}: a COLLADA file is UTF-8 XML text, this is not: {e}"))?;
    prescan_xml(path, text, false)?;
    let doc = roxmltree::Document::parse(text)
        .map_err(|e| format!("{file} is not well-formed XML: {e}"))?;
    let line = |n: roxmltree::Node| doc.text_pos_at(n.range().start).row;
    for n in doc.descendants().filter(|n| n.is_element()) {
        let Some(c) = n.attribute("count") else {
            continue;
        };
        let tag = n.tag_name().name();
        let Ok(count) = c.trim().parse::<u64>() else {
            return Err(format!(
                "{file} line {}: <{tag} count=\"{}\"> is not a whole number",
                line(n),
                crate::check::echoed(c)
            ));
        };
        let is_array = tag.ends_with("_array");
        let (needed, held, what) = match tag {
            "float_array" | "int_array" | "Name_array" | "IDREF_array" | "bool_array"
            | "SIDREF_array" | "token_array" => (count, tokens(n), "values it holds"),
            "triangles" | "lines" | "polylist" => {
                // mesh-loader reserves count x (3, 2, or the <vcount> sum) x stride indices,
                // stride = the largest <input offset> + 1: all must be in the <p>.
                let stride = n
                    .children()
                    .filter(|c| c.has_tag_name("input"))
                    .filter_map(|c| c.attribute("offset")?.trim().parse::<u64>().ok())
                    .max()
                    .unwrap_or(0)
                    .saturating_add(1);
                let per = match tag {
                    "triangles" => count.saturating_mul(3),
                    "lines" => count.saturating_mul(2),
                    _ => {
                        let vcount = n.children().filter(|c| c.has_tag_name("vcount"));
                        let words: Vec<&str> = vcount
                            .flat_map(|c| c.text().unwrap_or_default().split_ascii_whitespace())
                            .collect();
                        if count > words.len() as u64 {
                            return Err(format!(
                                "{file} line {}: <polylist count=\"{count}\"> but {} values in \
                                 its <vcount>; the count must match the data (re-export the mesh)",
                                line(n),
                                words.len()
                            ));
                        }
                        words
                            .iter()
                            .map(|w| w.parse::<u64>().unwrap_or(u64::MAX))
                            .fold(0, u64::saturating_add)
                    }
                };
                let p = n
                    .children()
                    .filter(|c| c.has_tag_name("p"))
                    .map(tokens)
                    .sum();
                (per.saturating_mul(stride), p, "indices of its <p>")
            }
            "polygons" | "linestrips" | "trifans" | "tristrips" => (
                count,
                n.children()
                    .filter(|c| c.has_tag_name("p"))
                    .map(tokens)
                    .sum(),
                "indices of its <p>",
            ),
            _ => continue,
        };
        // An empty array is not read (mesh-loader keeps it empty, whatever its count).
        if (is_array && held > 0 && needed != held) || (!is_array && needed > held) {
            return Err(format!(
                "{file} line {}: <{tag} count=\"{count}\"> needs {needed} but {held} {what}; \
                 the count must match the data (re-export the mesh)",
                line(n)
            ));
        }
    }
    Ok(())
}
