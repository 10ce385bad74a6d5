//! Unit tests of `files.rs`: excerpts, the URI sandbox, the reading helper.
use super::*;
use std::path::Path;

#[test]
fn excerpts_cut_long_words_and_keep_short_ones() {
    assert_eq!(excerpt("1e39"), "1e39");
    assert_eq!(quoted("1e39"), "\"1e39\"");
    let long = "9".repeat(1000);
    assert_eq!(excerpt(&long), format!("{}… (1000 bytes)", "9".repeat(40)));
    assert_eq!(
        quoted(&long),
        format!("\"{}\"… (1000 bytes)", "9".repeat(40))
    );
    // Cut on a character boundary.
    let wide = "é".repeat(100);
    assert!(excerpt(&wide).starts_with(&"é".repeat(40)));
}

#[test]
fn uris_stay_inside_the_base_folder() {
    let base = Path::new("models/car");
    for bad in ["../x.bin", "a/../../x.bin", "/etc/passwd", "./../x.bin"] {
        let e = resolve_inside(base, bad, false).unwrap_err();
        assert!(e.contains("outside the model's folder"), "{bad}: {e}");
        assert!(e.contains("--allow-outside-uris"), "{e}");
    }
    for good in ["x.bin", "a/../x.bin", "./a/b/x.bin"] {
        assert_eq!(resolve_inside(base, good, false).unwrap(), base.join(good));
    }
    assert_eq!(
        resolve_inside(base, "../x.bin", true).unwrap(),
        base.join("../x.bin")
    );
}

#[test]
fn only_regular_files_within_the_budget_are_read() {
    let dir = std::env::temp_dir().join(format!("luz-files-test-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let e = read_input(&dir).unwrap_err();
    assert!(e.to_string().contains("is a directory"), "{e}");
    let big = dir.join("big.bin");
    std::fs::File::create(&big)
        .unwrap()
        .set_len(InputBudget::DEFAULT.max_file_bytes + 1)
        .unwrap();
    let e = read_input(&big).unwrap_err();
    assert_eq!(e.kind(), std::io::ErrorKind::FileTooLarge);
    assert!(e.to_string().contains("--max-file-mb"), "{e}");
    let small = dir.join("small.txt");
    std::fs::write(&small, "abc").unwrap();
    assert_eq!(read_input_text(&small).unwrap(), "abc");
    let _ = std::fs::remove_dir_all(&dir);
}

/// A write that fails half way (a full disk: ENOSPC after part of the bytes) leaves neither
/// its temporary file nor a part of the file; the old contents stay.
#[test]
fn a_failed_write_leaves_nothing_behind() {
    let dir = std::env::temp_dir().join(format!("luz-files-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("a.lod");
    try_write_file_atomically(&path, b"old").unwrap();
    let full = write_atomically_with(&path, &[7u8; 1 << 20], |tmp, bytes| {
        std::fs::write(tmp, &bytes[..bytes.len() / 2])?;
        Err(std::io::Error::from_raw_os_error(28)) // ENOSPC
    });
    assert_eq!(full.unwrap_err().raw_os_error(), Some(28));
    let names: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect();
    assert_eq!(names, ["a.lod"]);
    assert_eq!(std::fs::read(&path).unwrap(), b"old");
    let _ = std::fs::remove_dir_all(&dir);
}
