//! `omnee`: once-more scattered next event estimation on the command line
//! (`omnee --help`); everything lives in the `omnee_cli` library.

fn main() {
    omnee_cli::cli::run();
}
