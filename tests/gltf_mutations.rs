//! A deterministic smoke fuzzer for the glTF loader on stable (the libFuzzer target is
//! `fuzz/fuzz_targets/gltf.rs`): the corpus's glTF files and a valid .glb, mutated byte-wise and
//! token-wise with a fixed seed, go through `luz::fuzzing::gltf`, which must not panic.
//! `LUZ_GLTF_MUTATIONS=N` runs N mutations instead of the default 3000, `LUZ_GLTF_SEED` another
//! sequence.

mod common;

use std::panic::{catch_unwind, AssertUnwindSafe};

use common::root;

/// xorshift64*.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_f491_4f6c_dd1d)
    }
    fn below(&mut self, n: usize) -> usize {
        (self.next() % n.max(1) as u64) as usize
    }
}

const TOKENS: &[&[u8]] = &[
    b"0",
    b"1",
    b"-1",
    b"4294967295",
    b"1e39",
    b"-0",
    b"null",
    b"[]",
    b"{}",
    b"\"\"",
    b"5126",
    b"5121",
    b"5125",
    b"5123",
    b"99",
    b"0.5",
    b"true",
    b"\"VEC4\"",
    b"\"MAT4\"",
    b"65536",
    b"\"MASK\"",
    b"\"BLEND\"",
    b"\"COLOR_0\"",
    b"\"TANGENT\"",
    b"2.0",
];

fn mutate(rng: &mut Rng, input: &[u8]) -> Vec<u8> {
    let mut v = input.to_vec();
    for _ in 0..1 + rng.below(4) {
        if v.is_empty() {
            v.push(b'{');
        }
        let i = rng.below(v.len());
        match rng.below(5) {
            0 => v[i] = rng.next() as u8,
            1 => {
                // Replace the number or token starting at i.
                let end = (i..v.len())
                    .find(|&k| !(v[k].is_ascii_alphanumeric() || b".-+\"".contains(&v[k])))
                    .unwrap_or(v.len());
                let t = TOKENS[rng.below(TOKENS.len())];
                v.splice(i..end.max(i), t.iter().copied());
            }
            2 => {
                let n = rng.below(16).min(v.len() - i);
                v.drain(i..i + n);
            }
            3 => v.truncate(i),
            _ => {
                let j = rng.below(v.len());
                let n = rng.below(32).min(v.len() - j);
                let chunk = v[j..j + n].to_vec();
                v.splice(i..i, chunk);
            }
        }
    }
    v
}

#[test]
fn mutated_gltf_files_do_not_panic() {
    let mut seeds: Vec<Vec<u8>> = ["tests/bad_inputs", "fuzz/seeds/gltf"]
        .iter()
        .flat_map(|d| std::fs::read_dir(root().join(d)).unwrap())
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|e| e == "gltf" || e == "glb"))
        .map(|p| std::fs::read(p).unwrap())
        .collect();
    seeds.sort();
    assert!(seeds.len() >= 20, "{} seeds", seeds.len());
    let valid: Vec<Vec<u8>> = std::fs::read_dir(root().join("fuzz/seeds/gltf"))
        .unwrap()
        .filter_map(|e| e.ok().map(|e| std::fs::read(e.path()).unwrap()))
        .collect();
    assert!(!valid.is_empty());
    let n: usize = std::env::var("LUZ_GLTF_MUTATIONS")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(3000);
    let seed = std::env::var("LUZ_GLTF_SEED")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(0x9e37_79b9_7f4a_7c15u64);
    let mut rng = Rng(seed | 1);
    let mut failed = Vec::new();
    for k in 0..n {
        // Mutations of valid files reach deeper than those of broken ones.
        let seed = if k % 3 == 0 {
            &seeds[k % seeds.len()]
        } else {
            &valid[k % valid.len()]
        };
        let input = mutate(&mut rng, seed);
        if catch_unwind(AssertUnwindSafe(|| luz::fuzzing::gltf(&input))).is_err() {
            failed.push(String::from_utf8_lossy(&input).into_owned());
            if failed.len() >= 3 {
                break;
            }
        }
    }
    assert!(
        failed.is_empty(),
        "panicked on:\n{}",
        failed.join("\n---\n")
    );
}
