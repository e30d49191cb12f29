//! The `sediment` program: the library's command line over every registered scene.

fn main() -> std::process::ExitCode {
    sediment::cli::main()
}
