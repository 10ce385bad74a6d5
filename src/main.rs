fn main() -> std::process::ExitCode {
    luz::cli::run()
}
