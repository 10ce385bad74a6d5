//! DOT and SVG output.

use luz_graph::*;

use crate::common::*;
use crate::scene::declare;

/// A minimal XML well-formedness check: tags balance, attributes are quoted, text has no raw
/// `<` or `&` outside entities.
fn check_xml(s: &str) -> Result<usize, String> {
    let mut stack: Vec<String> = Vec::new();
    let mut elements = 0;
    let mut rest = s;
    while let Some(i) = rest.find('<') {
        let text = &rest[..i];
        for (j, _) in text.match_indices('&') {
            let ent = &text[j..];
            if !["&amp;", "&lt;", "&gt;", "&quot;", "&apos;"]
                .iter()
                .any(|e| ent.starts_with(e))
            {
                return Err(format!("raw & in text: {text}"));
            }
        }
        let end = rest[i..].find('>').ok_or("unclosed <")? + i;
        let tag = &rest[i + 1..end];
        rest = &rest[end + 1..];
        if tag.starts_with('?') || tag.starts_with('!') {
            continue;
        }
        if !tag.matches('"').count().is_multiple_of(2) {
            return Err(format!("unbalanced quotes in <{tag}>"));
        }
        if let Some(name) = tag.strip_prefix('/') {
            let open = stack.pop().ok_or(format!("</{name}> without opening"))?;
            if open != name.trim() {
                return Err(format!("<{open}> closed by </{name}>"));
            }
        } else {
            elements += 1;
            let name = tag
                .split(|c: char| c.is_whitespace() || c == '/')
                .next()
                .unwrap_or("")
                .to_string();
            if !tag.ends_with('/') {
                stack.push(name);
            }
        }
    }
    if !stack.is_empty() {
        return Err(format!("unclosed: {stack:?}"));
    }
    if !rest.trim().is_empty() {
        return Err("text after the root".into());
    }
    Ok(elements)
}

fn scene_with_culled_pass() -> CompiledGraph<'static> {
    let mut g = FrameGraph::new();
    let s = declare(&mut g);
    let debug = g.create_image("debug <view> & co", color(8));
    g.pass("debug \"overlay\"")
        .read(s.hdr, Access::FragmentSampled)
        .write(debug, Access::ColorAttachmentWrite);
    g.compile().unwrap()
}

#[test]
fn dot_shows_every_pass_and_resource() {
    let c = scene_with_culled_pass();
    let dot = c.to_dot(&[("forward", 1.25), ("saturate", 0.5)]);
    assert!(dot.starts_with("digraph"));
    for p in &c.plan().passes {
        assert!(dot.contains(&p.name.replace('"', "\\\"")), "{}", p.name);
    }
    for i in &c.plan().images {
        assert!(dot.contains(&i.name), "{}", i.name);
    }
    assert!(dot.contains("readback"));
    assert!(dot.contains("1.250 ms"));
    assert!(dot.contains("culled"));
    assert!(dot.contains("style=\"dashed\", color=grey60"));
    assert!(dot.contains("label=\"FragmentSampled\""));
    assert!(dot.contains("R32G32B32A32_SFLOAT"));
    assert!(dot.contains("fillcolor=lightblue"));
    assert_eq!(dot.matches('{').count(), dot.matches('}').count());
}

#[test]
fn svg_is_wellformed_and_shows_everything() {
    let c = scene_with_culled_pass();
    let svg = c.to_svg(&[("forward", 1.25)]);
    let elements = check_xml(&svg).unwrap();
    assert!(elements > 20);
    assert!(svg.contains("<svg xmlns=\"http://www.w3.org/2000/svg\""));
    for p in &c.plan().passes {
        let escaped = p.name.replace('"', "&quot;");
        assert!(svg.contains(&format!(">{escaped}<")), "{}", p.name);
    }
    for name in ["hdr color", "depth", "shadow maps", "swapchain", "readback"] {
        assert!(svg.contains(&format!(">{name}<")), "{name}");
    }
    assert!(svg.contains("debug &lt;view&gt; &amp; co"));
    assert!(svg.contains("1.250 ms"));
    assert!(svg.contains(">culled<"));
    assert!(svg.contains(">TransferSrc<"));
    // The checker itself rejects broken documents.
    assert!(check_xml("<svg><g></svg>").is_err());
    assert!(check_xml("<svg><text>a & b</text></svg>").is_err());
}
