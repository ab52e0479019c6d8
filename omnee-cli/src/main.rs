//! `omnee`: the command-line front end (filled in by its own issue).

fn main() {
    eprintln!("omnee: no subcommands yet");
    std::process::exit(2);
}
