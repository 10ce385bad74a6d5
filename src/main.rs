mod cli;

fn main() -> std::process::ExitCode {
    // Rust ignores SIGPIPE, so printing into a closed pipe (`luz diff a b | head -1`) would panic in
    // println!. Behave like other command-line tools instead: end quietly.
    #[cfg(unix)]
    // SAFETY: called first, before any thread exists; SIG_DFL is a valid disposition for SIGPIPE.
    unsafe {
        libc::signal(libc::SIGPIPE, libc::SIG_DFL);
    }
    // lavapipe's rasterizer threads (luz::vk::host): read once, when the Vulkan driver loads, so
    // set before any Vulkan call; a value in the environment stands.
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    let var = luz::vk::host::RASTERIZER_THREADS_ENV;
    if let Some(n) = luz::vk::host::rasterizer_threads(std::env::var(var).ok().as_deref(), cores) {
        // SAFETY: still before any thread exists (first statements of main, nothing spawned yet),
        // so nothing reads the environment concurrently.
        unsafe { std::env::set_var(var, n.to_string()) };
    }
    cli::run()
}
