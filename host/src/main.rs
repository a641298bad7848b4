fn main() -> std::process::ExitCode {
    dashpot::cli::run()
}
