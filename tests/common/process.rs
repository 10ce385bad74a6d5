//! The `luz` binary as a child process. The child gets `LUZ_VALIDATION=1` (the validation layer on,
//! as in every test) and any other option through its own `Command`; the test process's
//! environment is never changed.

use std::ffi::OsStr;
use std::io::Write;
use std::path::Path;
use std::process::{Command, ExitStatus, Output, Stdio};

/// The `luz` binary built for these tests.
pub const LUZ: &str = env!("CARGO_BIN_EXE_luz");

/// `luz <args>` with the validation layer on, to adjust (`.env(…)`, `.current_dir(…)`, …) and
/// run with [`run`] / [`run_with_stdin`] (or spawn directly).
pub fn luz_command<I, S>(args: I) -> Command
where
    I: IntoIterator<Item = S>,
    S: AsRef<OsStr>,
{
    let mut cmd = Command::new(LUZ);
    cmd.args(args).env("LUZ_VALIDATION", "1");
    cmd
}

/// What a finished child process did.
#[derive(Debug)]
pub struct Ran {
    pub status: ExitStatus,
    /// The exit code, -1 when killed by a signal.
    pub code: i32,
    pub stdout: String,
    pub stderr: String,
}

impl Ran {
    fn from_output(what: &str, out: Output) -> Ran {
        let text = |bytes: Vec<u8>, stream: &str| {
            String::from_utf8(bytes).unwrap_or_else(|e| {
                panic!(
                    "{what} wrote non-UTF-8 to {stream}: {}",
                    String::from_utf8_lossy(e.as_bytes())
                )
            })
        };
        Ran {
            status: out.status,
            code: out.status.code().unwrap_or(-1),
            stdout: text(out.stdout, "stdout"),
            stderr: text(out.stderr, "stderr"),
        }
    }

    /// `(exit code, stdout, stderr)`.
    pub fn parts(self) -> (i32, String, String) {
        (self.code, self.stdout, self.stderr)
    }
}

/// Runs `cmd` to the end (stdin empty), capturing stdout and stderr.
pub fn run(cmd: &mut Command) -> Ran {
    let what = format!("{cmd:?}");
    let out = cmd
        .output()
        .unwrap_or_else(|e| panic!("cannot run {what}: {e}"));
    Ran::from_output(&what, out)
}

/// Runs `cmd` to the end with `stdin` as its standard input, capturing stdout and stderr.
pub fn run_with_stdin(cmd: &mut Command, stdin: &str) -> Ran {
    let what = format!("{cmd:?}");
    let mut child = cmd
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap_or_else(|e| panic!("cannot run {what}: {e}"));
    let mut pipe = child.stdin.take().unwrap();
    let text = stdin.to_owned();
    // From another thread, so that a child writing much before reading all of it cannot block.
    let writer = std::thread::spawn(move || pipe.write_all(text.as_bytes()));
    let out = child.wait_with_output().unwrap();
    writer
        .join()
        .unwrap()
        .unwrap_or_else(|e| panic!("cannot write the stdin of {what}: {e}"));
    Ran::from_output(&what, out)
}

/// `luz <args>` with the validation layer on: `(exit code, stdout, stderr)`.
pub fn luz(args: &[&str]) -> (i32, String, String) {
    run(&mut luz_command(args)).parts()
}

/// `xvfb-run -a luz <args>` (a real X server and window; validation on, the IBL cache in this
/// build's `target/tmp`, not the user's), or None with a visible note when xvfb-run is missing.
pub fn luz_in_window(args: &[&str]) -> Option<(i32, String, String)> {
    luz_in_window_with(args, &[])
}

/// [`luz_in_window`] with more variables for the child (say `LUZ_SYNC_VALIDATION=1`).
pub fn luz_in_window_with(args: &[&str], env: &[(&str, &str)]) -> Option<(i32, String, String)> {
    let have = Command::new("xvfb-run").arg("--help").output().is_ok();
    if !have {
        eprintln!("SKIPPED: xvfb-run is not installed (scripts/setup.sh installs it)");
        return None;
    }
    // Our own X authority file (one per run): without `-f`, xvfb-run makes a temporary folder
    // for it and exits 5 instead of luz's status when removing that folder fails, which
    // happened once with several X servers running in parallel (2026-11-26).
    static RUNS: std::sync::atomic::AtomicUsize = std::sync::atomic::AtomicUsize::new(0);
    let n = RUNS.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
    let auth =
        Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!("xauth-{}-{n}", std::process::id()));
    std::fs::write(&auth, b"").unwrap_or_else(|e| panic!("{}: {e}", auth.display()));
    let mut cmd = Command::new("xvfb-run");
    cmd.args(["-a", "-s", "-screen 0 1600x1000x24", "-f"])
        .arg(&auth)
        .arg(LUZ)
        .args(args)
        .env("LUZ_VALIDATION", "1")
        .env(
            "LUZ_CACHE_DIR",
            Path::new(env!("CARGO_TARGET_TMPDIR")).join("luz-viewer-cache"),
        )
        .envs(env.iter().copied());
    let ran = run(&mut cmd).parts();
    let _ = std::fs::remove_file(&auth);
    Some(ran)
}

/// A run that must have succeeded with the validation layer silent: exit 0, no panic, the
/// summary line `validation: 0 errors, 0 warnings` on stderr.
pub fn assert_ran_clean(code: i32, out: &str, err: &str) {
    assert_eq!(code, 0, "luz failed\nstdout: {out}\nstderr: {err}");
    assert!(!err.contains("panicked"), "{err}");
    assert!(
        err.contains("validation: 0 errors, 0 warnings"),
        "validation must be silent: {err}"
    );
}
