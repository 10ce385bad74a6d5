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

/// `cmd` run under an address-space ceiling of `bytes` (`RLIMIT_AS`, set in the child before
/// `exec`, as `prlimit --as` does): an allocation beyond it fails in the child, which aborts or
/// reports it, and the test sees a non-zero exit instead of a machine out of memory.
pub fn with_memory_ceiling(cmd: &mut Command, bytes: u64) -> &mut Command {
    with_limits(cmd, bytes, None)
}

/// [`with_memory_ceiling`] and, with `file_bytes`, a largest file the child may write
/// (`RLIMIT_FSIZE`): a write beyond it kills the child with SIGXFSZ mid-write, as a crash or
/// `kill -9` would.
pub fn with_limits(cmd: &mut Command, bytes: u64, file_bytes: Option<u64>) -> &mut Command {
    use std::os::unix::process::CommandExt;
    // SAFETY: setrlimit is async-signal-safe, and the closure touches nothing else.
    unsafe {
        cmd.pre_exec(move || {
            let set = |resource, value: u64| {
                let lim = libc::rlimit {
                    rlim_cur: value,
                    rlim_max: value,
                };
                if libc::setrlimit(resource, &lim) != 0 {
                    return Err(std::io::Error::last_os_error());
                }
                Ok(())
            };
            set(libc::RLIMIT_AS, bytes)?;
            if let Some(f) = file_bytes {
                set(libc::RLIMIT_FSIZE, f)?;
            }
            Ok(())
        })
    }
}

/// `cmd` with SIGXFSZ ignored (inherited through `exec`): with [`with_limits`]' largest file, a
/// write beyond it then fails with EFBIG instead of killing the child, as a full disk would.
pub fn as_if_the_disk_were_full(cmd: &mut Command) -> &mut Command {
    use std::os::unix::process::CommandExt;
    // SAFETY: signal() is async-signal-safe, and the closure touches nothing else.
    unsafe {
        cmd.pre_exec(|| {
            if libc::signal(libc::SIGXFSZ, libc::SIG_IGN) == libc::SIG_ERR {
                return Err(std::io::Error::last_os_error());
            }
            Ok(())
        })
    }
}

/// Runs `cmd` like [`run`], killed (and the test failed) after `timeout`: for inputs that once
/// never finished. Its output is read while it runs, so a talkative child cannot block.
pub fn run_within(cmd: &mut Command, timeout: std::time::Duration) -> Ran {
    use std::io::Read;
    let what = format!("{cmd:?}");
    let mut child = cmd
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap_or_else(|e| panic!("cannot run {what}: {e}"));
    let drain = |mut r: Box<dyn Read + Send>| {
        std::thread::spawn(move || {
            let mut v = Vec::new();
            let _ = r.read_to_end(&mut v);
            v
        })
    };
    let out = drain(Box::new(child.stdout.take().unwrap()));
    let err = drain(Box::new(child.stderr.take().unwrap()));
    let t0 = std::time::Instant::now();
    let status = loop {
        if let Some(s) = child.try_wait().unwrap() {
            break s;
        }
        if t0.elapsed() > timeout {
            let _ = child.kill();
            let _ = child.wait();
            panic!("{what} still running after {timeout:?}");
        }
        std::thread::sleep(std::time::Duration::from_millis(20));
    };
    let output = Output {
        status,
        stdout: out.join().unwrap(),
        stderr: err.join().unwrap(),
    };
    Ran::from_output(&what, output)
}

/// The ceiling of a run that starts Vulkan (lavapipe and LLVM reserve address space): enough
/// for a small render, far below what the unbounded cases of issue 38 took (gigabytes).
pub const GPU_MEMORY_CEILING: u64 = 2048 << 20;
