//! Unit tests of the chart helpers: ticks, number format, fitting, rendering.

use super::*;

#[test]
fn numbers_and_ticks() {
    assert_eq!(format_number(0.0), "0");
    assert_eq!(format_number(0.25), "0.25");
    assert_eq!(format_number(1.0), "1");
    assert_eq!(format_number(1234.4), "1234");
    assert_eq!(format_number(1e-5), "1e-5");
    assert_eq!(ring_ticks(1.0), vec![0.25, 0.5, 0.75, 1.0]);
    assert_eq!(ring_ticks(44.0), vec![10.0, 20.0, 30.0, 40.0, 50.0]);
    assert_eq!(*ring_ticks(0.31).last().unwrap(), 0.4);
    assert_eq!(viridis(0.0), RGBColor(68, 1, 84));
    assert_eq!(viridis(1.0), RGBColor(253, 231, 37));
}

fn non_white(rgb: &[u8]) -> usize {
    rgb.chunks(3).filter(|p| *p != [255, 255, 255]).count()
}

/// Every chart kind renders (log axes, labels, full polar, linear heatmap). Needs the font.
#[test]
fn every_chart_kind_renders() {
    let line = LineChart {
        title: "line".into(),
        x: Axis::new("x").log(),
        y: Axis::new("y").log(),
        series: vec![
            Series::new("a", (1..50).map(|i| (i as f64, (i * i) as f64)).collect()).markers(),
            Series::new("b", vec![(1.0, 1.0), (0.0, 5.0), (50.0, 10.0)]).dashed(),
        ],
        legend: Legend::UpperLeft,
    };
    let scatter = ScatterChart {
        title: "speed against accuracy".into(),
        x: Axis::new("ms").log(),
        y: Axis::new("error"),
        points: vec![
            LabeledPoint {
                x: 0.5,
                y: 0.1,
                label: "split sum".into(),
                group: 0,
            },
            LabeledPoint {
                x: 4.0,
                y: 0.01,
                label: "128 samples".into(),
                group: 1,
            },
        ],
        groups: vec!["a".into(), "b".into()],
        legend: Legend::UpperRight,
    };
    let heat = Heatmap {
        title: "heat".into(),
        x: Axis::new("x").range(0.0, 1.0),
        y: Axis::new("y").range(-1.0, 1.0),
        nx: 3,
        ny: 2,
        values: vec![0.0, 1.0, 2.0, f64::NAN, 4.0, 5.0],
        color_label: "v".into(),
        empty_label: "none".into(),
        ..Default::default()
    };
    let polar = PolarChart {
        title: "polar".into(),
        series: vec![PolarSeries {
            label: "circle".into(),
            points: (0..=360).map(|a| (a as f64 - 180.0, 2.0)).collect(),
            color: None,
            rays: vec![45.0],
        }],
        r_max: None,
        half: false,
        r_label: "r".into(),
    };
    for chart in [line.into(), scatter.into(), heat.into(), polar.into()] {
        let rgb = render_rgb(&chart, 400, 300).unwrap();
        assert_eq!(rgb.len(), 400 * 300 * 3);
        assert!(non_white(&rgb) > 400 * 300 / 50, "{chart:?}");
    }
    assert!(Format::from_path(Path::new("a.jpg")).is_err());
    assert_eq!(Format::from_path(Path::new("a.SVG")).unwrap(), Format::Svg);
}

/// Charts record their provenance: the caller's entries plus the title, size and encoding, in
/// the PNG's text chunks and the SVG's metadata element, read back by `luz info`'s readers.
#[test]
fn charts_carry_provenance() {
    let chart: Chart = LineChart {
        title: "a <title> & more".into(),
        x: Axis::new("x"),
        y: Axis::new("y"),
        series: vec![Series::new("a", vec![(0.0, 1.0), (1.0, 2.0)])],
        legend: Legend::UpperLeft,
    }
    .into();
    let dir = std::env::temp_dir().join(format!("luz-plot-meta-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let mut meta = crate::imageio::Provenance::base();
    meta.set("luz.scene", "scenes/x.json");
    let [png, svg] = save_png_svg_with(&chart, &dir.join("c"), (320, 200), &meta).unwrap();
    let from_png = crate::imageio::provenance::read(&png).unwrap();
    let from_svg = crate::imageio::provenance::read_svg(&svg).unwrap();
    for p in [&from_png, &from_svg] {
        assert_eq!(p.get("luz.scene"), Some("scenes/x.json"), "{p:?}");
        assert_eq!(p.get("luz.chart"), Some("a <title> & more"), "{p:?}");
        assert_eq!(p.get("luz.size"), Some("320x200"), "{p:?}");
        assert!(p.get("luz.version").is_some(), "{p:?}");
    }
    assert_eq!(from_svg.get("luz.encoding"), Some("SVG chart"));
    // The SVG stays well-formed: the metadata sits inside the root element.
    let text = std::fs::read_to_string(&svg).unwrap();
    let (svg_open, meta_at) = (text.find("<svg").unwrap(), text.find("<metadata").unwrap());
    assert!(svg_open < meta_at && text.contains("&lt;title&gt; &amp; more"));
    std::fs::remove_dir_all(dir).unwrap();
}
