//! The layering rules docs/architecture.md promises, checked on the sources:
//! - no import circles: inside every module folder (a crate's `src` included), the modules that are
//!   its children use each other along a DAG (a file using its own parent's items is fine — that
//!   is how a folder's `mod.rs` re-exports its children — siblings in a loop are not);
//! - the core crate names neither `ash` nor `shaderc`, in its sources or its manifest;
//! - pipeline barriers are recorded by the frame graph and the vk layer only: no other file calls
//!   `cmd_pipeline_barrier`/`cmd_pipeline_barrier2`, and neither `headless.rs` nor `window/`
//!   records a layout transition by hand.
//!
//! Tests (`tests.rs` files and `#[cfg(test)]` modules) are left out: a test may reach anywhere.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// Every crate's source folder: the binary's `src` and each `crates/*/src`.
fn source_roots() -> Vec<PathBuf> {
    let mut roots = vec![root().join("src")];
    let mut crates: Vec<PathBuf> = std::fs::read_dir(root().join("crates"))
        .expect("crates/")
        .map(|e| e.unwrap().path().join("src"))
        .filter(|p| p.is_dir())
        .collect();
    crates.sort();
    roots.extend(crates);
    roots
}

fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    let mut entries: Vec<PathBuf> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    entries.sort();
    for p in entries {
        if p.is_dir() {
            rust_files(&p, out);
        } else if p.extension().is_some_and(|e| e == "rs") {
            out.push(p);
        }
    }
}

/// The file's code without comments and without its `#[cfg(test)]` modules, wherever they sit
/// (a module in the middle of a file once hid the code after it from these checks).
fn code_of(text: &str) -> String {
    let mut kept = String::new();
    let mut rest = text;
    while let Some(at) = test_module_at(rest) {
        kept.push_str(&rest[..at]);
        rest = &rest[at..];
        rest = match (rest.find('{'), rest.find(';')) {
            // `#[cfg(test)] mod name { … }`: skip to its closing brace (braces counted; an
            // unbalanced count, e.g. from a brace in a string, cuts the file there instead).
            (Some(open), semi) if semi.is_none_or(|s| open < s) => {
                match closing_brace(&rest[open..]) {
                    Some(close) => &rest[open + close + 1..],
                    None => "",
                }
            }
            // `#[cfg(test)] mod name;`: a file of its own.
            (_, Some(semi)) => &rest[semi + 1..],
            _ => "",
        };
    }
    kept.push_str(rest);
    let mut out = String::new();
    for line in kept.lines() {
        let line = match line.find("//") {
            Some(i) => &line[..i],
            None => line,
        };
        out.push_str(line);
        out.push('\n');
    }
    out
}

/// Where the next test module (`#[cfg(test)]` then `mod` or `pub mod`) starts in `text`.
fn test_module_at(text: &str) -> Option<usize> {
    ["#[cfg(test)]\nmod ", "#[cfg(test)]\npub mod "]
        .iter()
        .filter_map(|m| text.find(m))
        .min()
}

/// The offset of the brace closing the one `text` starts with.
fn closing_brace(text: &str) -> Option<usize> {
    let mut depth = 0usize;
    for (i, c) in text.char_indices() {
        match c {
            '{' => depth += 1,
            '}' => {
                depth = depth.checked_sub(1)?;
                if depth == 0 {
                    return Some(i);
                }
            }
            _ => {}
        }
    }
    None
}

/// A module's path inside its crate (`["render", "forward", "variant"]`); `lib.rs` / `main.rs`
/// is the crate root (empty), `mod.rs` its folder.
fn module_of(src: &Path, file: &Path) -> Vec<String> {
    let rel = file.strip_prefix(src).unwrap();
    let mut parts: Vec<String> = rel
        .iter()
        .map(|c| c.to_string_lossy().into_owned())
        .collect();
    let last = parts.pop().unwrap();
    let stem = last.trim_end_matches(".rs");
    if !(stem == "mod" || (parts.is_empty() && (stem == "lib" || stem == "main"))) {
        parts.push(stem.to_string());
    }
    parts
}

/// Every `use` tree and `crate::`/`super::` path in `code`, expanded to paths of identifiers.
fn referenced_paths(code: &str) -> Vec<Vec<String>> {
    let mut out = Vec::new();
    // `use` statements, braces expanded.
    let mut rest = code;
    while let Some(i) = find_word(rest, "use") {
        let after = &rest[i + 3..];
        let Some(end) = after.find(';') else { break };
        expand(after[..end].trim(), &mut Vec::new(), &mut out);
        rest = &after[end..];
    }
    // Inline paths.
    for start in ["crate::", "super::", "self::"] {
        let mut from = 0;
        while let Some(i) = code[from..].find(start) {
            let at = from + i;
            from = at + start.len();
            let before = code[..at].chars().next_back();
            if before.is_some_and(|c| c.is_alphanumeric() || c == '_') {
                continue;
            }
            let path: String = code[at..]
                .chars()
                .take_while(|c| c.is_alphanumeric() || *c == '_' || *c == ':')
                .collect();
            out.push(
                path.split("::")
                    .filter(|s| !s.is_empty())
                    .map(str::to_string)
                    .collect(),
            );
        }
    }
    out
}

fn find_word(text: &str, word: &str) -> Option<usize> {
    let mut from = 0;
    while let Some(i) = text[from..].find(word) {
        let at = from + i;
        let before = text[..at].chars().next_back();
        let after = text[at + word.len()..].chars().next();
        let boundary = |c: Option<char>| !c.is_some_and(|c| c.is_alphanumeric() || c == '_');
        if boundary(before) && after.is_some_and(char::is_whitespace) {
            return Some(at);
        }
        from = at + word.len();
    }
    None
}

/// Whether `ident` stands in `code` as a whole identifier (`ash::vk`, `use ash;`), not inside
/// another (`std::hash::Hash`).
fn names_ident(code: &str, ident: &str) -> bool {
    let is_ident = |c: Option<char>| c.is_some_and(|c| c.is_alphanumeric() || c == '_');
    code.match_indices(ident).any(|(at, _)| {
        !is_ident(code[..at].chars().next_back())
            && !is_ident(code[at + ident.len()..].chars().next())
    })
}

/// Expands a `use` tree (`a::{b, c::{d, e}}`) below `prefix`.
fn expand(tree: &str, prefix: &mut Vec<String>, out: &mut Vec<Vec<String>>) {
    let tree = tree.trim();
    if let Some(open) = tree.find('{') {
        let head: Vec<String> = tree[..open]
            .split("::")
            .map(str::trim)
            .filter(|s| !s.is_empty())
            .map(str::to_string)
            .collect();
        let inner = &tree[open + 1..tree.rfind('}').unwrap_or(tree.len())];
        let n = prefix.len();
        prefix.extend(head);
        let mut depth = 0;
        let mut part = String::new();
        for c in inner.chars() {
            match c {
                '{' => depth += 1,
                '}' => depth -= 1,
                _ => {}
            }
            if c == ',' && depth == 0 {
                expand(&part, prefix, out);
                part.clear();
            } else {
                part.push(c);
            }
        }
        if !part.trim().is_empty() {
            expand(&part, prefix, out);
        }
        prefix.truncate(n);
    } else {
        let tree = tree.split(" as ").next().unwrap_or(tree);
        let mut p = prefix.clone();
        p.extend(
            tree.split("::")
                .map(str::trim)
                .filter(|s| !s.is_empty() && *s != "*")
                .map(str::to_string),
        );
        out.push(p);
    }
}

/// The module a path starting in `from` names (the longest prefix that is a module of the
/// crate), or `None` for other crates and the standard library.
fn resolve(
    path: &[String],
    from: &[String],
    modules: &BTreeSet<Vec<String>>,
) -> Option<Vec<String>> {
    let mut base: Vec<String>;
    let mut rest = path;
    match path.first().map(String::as_str) {
        Some("crate") => {
            base = Vec::new();
            rest = &path[1..];
        }
        Some("super") | Some("self") => {
            base = from.to_vec();
            while let Some(first) = rest.first() {
                match first.as_str() {
                    "super" => {
                        base.pop();
                    }
                    "self" => {}
                    _ => break,
                }
                rest = &rest[1..];
            }
        }
        _ => return None,
    }
    let mut best = base.clone();
    for seg in rest {
        base.push(seg.clone());
        if modules.contains(&base) {
            best = base.clone();
        } else {
            break;
        }
    }
    Some(best)
}

/// Cycles among the children of every module folder: (folder, one cycle as child names).
fn import_cycles(src: &Path) -> Vec<(String, Vec<String>)> {
    let mut files = Vec::new();
    rust_files(src, &mut files);
    let files: Vec<PathBuf> = files
        .into_iter()
        .filter(|f| {
            let name = f.file_name().unwrap().to_string_lossy();
            !(name == "tests.rs" || name.ends_with("_tests.rs"))
        })
        .collect();
    let modules: BTreeSet<Vec<String>> = files.iter().map(|f| module_of(src, f)).collect();
    // Edges between modules (file level).
    let mut edges: BTreeSet<(Vec<String>, Vec<String>)> = BTreeSet::new();
    for f in &files {
        let from = module_of(src, f);
        let code = code_of(&std::fs::read_to_string(f).unwrap());
        for p in referenced_paths(&code) {
            if let Some(to) = resolve(&p, &from, &modules) {
                if to != from {
                    edges.insert((from.clone(), to));
                }
            }
        }
    }
    let mut cycles = Vec::new();
    for folder in &modules {
        // Children of `folder`: the next segment of every module strictly below it.
        let child = |m: &Vec<String>| -> Option<String> {
            (m.len() > folder.len() && m.starts_with(folder)).then(|| m[folder.len()].clone())
        };
        let mut graph: BTreeMap<String, BTreeSet<String>> = BTreeMap::new();
        for (a, b) in &edges {
            if let (Some(ca), Some(cb)) = (child(a), child(b)) {
                if ca != cb {
                    graph.entry(ca).or_default().insert(cb);
                }
            }
        }
        if let Some(cycle) = find_cycle(&graph) {
            cycles.push((folder.join("::"), cycle));
        }
    }
    cycles
}

fn find_cycle(graph: &BTreeMap<String, BTreeSet<String>>) -> Option<Vec<String>> {
    // 0 unvisited, 1 on the stack, 2 done.
    fn visit(
        n: &str,
        graph: &BTreeMap<String, BTreeSet<String>>,
        state: &mut BTreeMap<String, u8>,
        stack: &mut Vec<String>,
    ) -> Option<Vec<String>> {
        state.insert(n.to_string(), 1);
        stack.push(n.to_string());
        for m in graph.get(n).into_iter().flatten() {
            match state.get(m.as_str()).copied().unwrap_or(0) {
                1 => {
                    let i = stack.iter().position(|s| s == m).unwrap();
                    let mut c = stack[i..].to_vec();
                    c.push(m.clone());
                    return Some(c);
                }
                0 => {
                    if let Some(c) = visit(m, graph, state, stack) {
                        return Some(c);
                    }
                }
                _ => {}
            }
        }
        stack.pop();
        state.insert(n.to_string(), 2);
        None
    }
    let mut state = BTreeMap::new();
    for n in graph.keys() {
        if state.get(n.as_str()).copied().unwrap_or(0) == 0 {
            if let Some(c) = visit(n, graph, &mut state, &mut Vec::new()) {
                return Some(c);
            }
        }
    }
    None
}

#[test]
fn no_import_circles_in_any_crate() {
    let mut all = Vec::new();
    for src in source_roots() {
        for (folder, cycle) in import_cycles(&src) {
            all.push(format!(
                "{}: in {}: {}",
                src.strip_prefix(root()).unwrap().display(),
                if folder.is_empty() {
                    "the crate root"
                } else {
                    &folder
                },
                cycle.join(" → ")
            ));
        }
    }
    assert!(all.is_empty(), "import circles:\n{}", all.join("\n"));
}

/// The checker finds the kind of circle it is meant to: siblings in a loop, not a parent
/// re-exporting its children.
#[test]
fn the_cycle_checker_sees_sibling_loops_only() {
    let dir = std::env::temp_dir().join(format!("luz-layers-{}", std::process::id()));
    let src = dir.join("src");
    std::fs::create_dir_all(src.join("a")).unwrap();
    std::fs::write(src.join("lib.rs"), "pub mod a;\npub mod b;\n").unwrap();
    std::fs::write(
        src.join("a/mod.rs"),
        "mod x;\nmod y;\npub use x::X;\npub struct A;\n",
    )
    .unwrap();
    std::fs::write(src.join("a/x.rs"), "use super::A;\npub struct X;\n").unwrap();
    std::fs::write(src.join("a/y.rs"), "use super::x::X;\n").unwrap();
    std::fs::write(src.join("b.rs"), "use crate::a::A;\n").unwrap();
    assert!(import_cycles(&src).is_empty(), "{:?}", import_cycles(&src));
    // x → y → x, and a → b → a.
    std::fs::write(src.join("a/x.rs"), "use super::{y, A};\npub struct X;\n").unwrap();
    std::fs::write(
        src.join("a/mod.rs"),
        "mod x;\nmod y;\npub use x::X;\npub struct A;\nfn f() { crate::b::g(); }\n",
    )
    .unwrap();
    let found = import_cycles(&src);
    let _ = std::fs::remove_dir_all(&dir);
    assert_eq!(found.len(), 2, "{found:?}");
}

#[test]
fn the_core_crate_knows_no_vulkan() {
    let core = root().join("crates/luz-core");
    let manifest = std::fs::read_to_string(core.join("Cargo.toml")).unwrap();
    for dep in ["ash", "shaderc", "gpu-allocator"] {
        assert!(
            !manifest.lines().any(|l| l.trim_start().starts_with(dep)),
            "crates/luz-core/Cargo.toml depends on {dep}"
        );
    }
    let mut files = Vec::new();
    rust_files(&core.join("src"), &mut files);
    for f in files {
        let code = code_of(&std::fs::read_to_string(&f).unwrap());
        assert!(!names_ident(&code, "ash"), "{} names ash", f.display());
    }
}

#[test]
fn barriers_are_recorded_by_the_graph_and_the_vk_layer_only() {
    let mut offenders = Vec::new();
    for src in source_roots() {
        let mut files = Vec::new();
        rust_files(&src, &mut files);
        for f in files {
            let rel = f
                .strip_prefix(root())
                .unwrap()
                .to_string_lossy()
                .into_owned();
            let allowed = rel.starts_with("crates/luz-graph/") || rel.contains("/src/vk/");
            let code = code_of(&std::fs::read_to_string(&f).unwrap());
            if !allowed && code.contains("cmd_pipeline_barrier") {
                offenders.push(format!("{rel}: cmd_pipeline_barrier"));
            }
            let frame = rel.ends_with("/headless.rs") || rel.starts_with("src/window/");
            if frame && (code.contains("transition(") || code.contains("Transition {")) {
                offenders.push(format!("{rel}: a hand-written transition"));
            }
        }
    }
    assert!(offenders.is_empty(), "{}", offenders.join("\n"));
}

/// Issue 33: descriptor set layouts, pools and writes come from the shaders' reflected
/// interfaces (`luz_gpu::vk::interface`); no code outside the vk layer restates a binding.
#[test]
fn descriptor_layouts_are_made_from_the_shaders_only() {
    let hand_written = [
        "DescriptorSetLayoutBinding",
        "DescriptorPoolSize",
        "PushConstantRange",
        "WriteDescriptorSet",
        "update_descriptor_sets",
        "DescriptorSetLayout::new",
        "PipelineLayout::new",
    ];
    let mut offenders = Vec::new();
    let mut seen_vk = false;
    for src in source_roots() {
        let mut files = Vec::new();
        rust_files(&src, &mut files);
        for f in files {
            let rel = f
                .strip_prefix(root())
                .unwrap()
                .to_string_lossy()
                .into_owned();
            let code = code_of(&std::fs::read_to_string(&f).unwrap());
            if rel.contains("/src/vk/") {
                seen_vk |= code.contains("update_descriptor_sets");
                continue;
            }
            for word in hand_written {
                if code.contains(word) {
                    offenders.push(format!("{rel}: {word}"));
                }
            }
        }
    }
    // The check looks where it should: the vk layer does write descriptors.
    assert!(seen_vk, "no update_descriptor_sets found in the vk layer");
    assert!(offenders.is_empty(), "{}", offenders.join("\n"));
}

/// Issue 33: rendering is switched by options (recorded in provenance), never by environment
/// variables read inside the library. The only `LUZ_` variables library code may read are the
/// documented device, validation, host-tuning and file-location ones (docs/cli.md).
#[test]
fn library_code_reads_only_the_documented_luz_variables() {
    let allowed = [
        "LUZ_CACHE_DIR",
        "LUZ_DEVICE",
        "LUZ_VALIDATION",
        "LUZ_SYNC_VALIDATION",
        "LUZ_MALLOC_TUNING",
        "LUZ_FONT",
        "LUZ_GIT_COMMIT",
    ];
    let cli = std::fs::read_to_string(root().join("docs/cli.md")).unwrap();
    let mut offenders = Vec::new();
    let mut found = std::collections::BTreeSet::new();
    for src in source_roots() {
        let mut files = Vec::new();
        rust_files(&src, &mut files);
        for f in files {
            let rel = f
                .strip_prefix(root())
                .unwrap()
                .to_string_lossy()
                .into_owned();
            let code = code_of(&std::fs::read_to_string(&f).unwrap());
            for (i, _) in code.match_indices("\"LUZ_") {
                let name: String = code[i + 1..]
                    .chars()
                    .take_while(|c| c.is_ascii_uppercase() || *c == '_')
                    .collect();
                if !allowed.contains(&name.as_str()) {
                    offenders.push(format!("{rel}: {name}"));
                }
                found.insert(name);
            }
        }
    }
    assert!(offenders.is_empty(), "{}", offenders.join("\n"));
    // The scan sees the variables that are there, and each is documented.
    assert!(found.contains("LUZ_CACHE_DIR"), "{found:?}");
    for name in found.iter().filter(|n| *n != "LUZ_GIT_COMMIT") {
        assert!(cli.contains(name.as_str()), "{name} is not in docs/cli.md");
    }
}

/// `code_of` drops a test module in the middle of a file and keeps the code after it.
#[test]
fn code_of_skips_test_modules_anywhere() {
    let text = "fn a() {}\n#[cfg(test)]\nmod tests {\n    fn t() { let _ = format!(\"{}\", 1); }\n}\nfn b() {} // b\n#[cfg(test)]\nmod more;\nfn c() {}\n";
    let code = code_of(text);
    assert!(
        code.contains("fn a()") && code.contains("fn b()") && code.contains("fn c()"),
        "{code}"
    );
    assert!(
        !code.contains("fn t()") && !code.contains("mod more") && !code.contains("// b"),
        "{code}"
    );
}
