//! `omnee`: once-more scattered next event estimation on the command line
//! (`omnee --help`). A thin front end of the `omnee-render` library:
//! [`cli`] parses and dispatches, [`commands`] translates each subcommand's
//! options, calls the library and prints, [`progress`] draws the render's
//! progress bar and [`named`] hands the library's closed sets of names to
//! clap.

mod cli;
mod commands;
mod named;
mod progress;

fn main() {
    cli::run();
}
