//! The command line in one place: the subcommands, clap's parsing (with
//! errors about closed sets of names in the CLI's own form), and the
//! dispatch to each subcommand's `run` in [`crate::commands`].

use crate::commands::default_scene::{self, DefaultSceneArgs};
use crate::commands::estimate::{self, EstimateArgs};
use crate::commands::merge::{self, MergeArgs};
use crate::commands::probe::{self, ProbeArgs};
use crate::commands::render::{self, RenderArgs};
use crate::commands::samples::{self, SamplesArgs};
use clap::error::{ContextKind, ContextValue, ErrorKind};
use clap::{Parser, Subcommand};
use omnee_core::method::Choice;
use omnee_core::names::Named;
use omnee_core::phase::PhaseKind;
use omnee_render::RenderError;

const EXIT_CODES: &str = "\
Exit codes: 0 success, 1 a file could not be written, 2 bad input (the message names
the field, its value and the allowed range; also an answer beyond f64's range and a
--reference whose quadrature spent its budget), 130 cancelled.
Limits: --samples [1, 2^40], samples --count [1, 2^24], --threads [0, 1024],
--spp [1, 2^24] and 2^40 samples in all, --time (0, 604800] seconds.";

/// The text after the options: the phase specs (the core's [`PhaseKind`]s),
/// the techniques (the core's [`Choice`]s) and the exit codes.
fn after_help() -> String {
    let specs: Vec<String> = PhaseKind::ALL
        .iter()
        .map(|k| format!("  {:<20}{}", k.usage(), k.help()))
        .collect();
    let techniques: Vec<String> = Choice::ALL
        .iter()
        .map(|t| format!("  {:<12} {}", t.name(), wrap(t.help(), 80, 15)))
        .collect();
    format!(
        "Phase function specs (scene files' medium.phase and --phase):\n{}\n\
         Angles are deflections between propagation directions (0 = straight on).\n\n\
         Techniques for the once-more term (--technique):\n{}\n\n{EXIT_CODES}",
        specs.join("\n"),
        techniques.join("\n")
    )
}

/// `text` broken into lines of at most `width` characters (at spaces),
/// lines after the first indented by `indent`.
fn wrap(text: &str, width: usize, indent: usize) -> String {
    let mut out = String::new();
    let mut line = 0;
    for word in text.split_whitespace() {
        if line > 0 && line + 1 + word.len() > width {
            out.push('\n');
            out.push_str(&" ".repeat(indent));
            line = 0;
        } else if line > 0 {
            out.push(' ');
            line += 1;
        }
        out.push_str(word);
        line += word.len();
    }
    out
}

/// omnee: once-more scattered next event estimation for volume rendering.
#[derive(Parser, Debug)]
#[command(name = "omnee", version, about, after_help = after_help())]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand, Debug)]
enum Command {
    /// Render a scene (default: the built-in one) to EXR (a layer per term) and PNG.
    #[command(after_help = after_help())]
    Render(RenderArgs),
    /// Irradiance at a point of a scene, per term, as mean and standard error.
    #[command(after_help = after_help())]
    Probe(ProbeArgs),
    /// The point-to-point once-more integral in an infinite homogeneous medium.
    #[command(after_help = after_help())]
    Estimate(EstimateArgs),
    /// The x1 samples of a technique with their pdf and weight.
    #[command(after_help = after_help())]
    Samples(SamplesArgs),
    /// Sum EXR files rendered with disjoint --crop windows into one image.
    Merge(MergeArgs),
    /// Print a built-in scene (TOML, every field documented).
    DefaultScene(DefaultSceneArgs),
}

/// The flag of clap's `--samples <SAMPLES>` (or the name of `[SCENE]`).
fn flag(arg: &str) -> &str {
    arg.split_whitespace().next().unwrap_or(arg)
}

/// A clap error in the CLI's form: a value outside a closed set of names,
/// `--technique = "magic" is not a technique; allowed: omnee, ...` (the
/// noun is the option's value name), or a value an option's parser refused,
/// `--samples = 1e30 is out of range; allowed: [1, 2^40]` (the parser's
/// message, which names the allowed range, after the flag).
fn invalid_name(e: &clap::Error) -> Option<RenderError> {
    if e.kind() == ErrorKind::ValueValidation {
        let (Some(ContextValue::String(arg)), Some(source)) =
            (e.get(ContextKind::InvalidArg), std::error::Error::source(e))
        else {
            return None;
        };
        // The CLI's parsers name the allowed range; clap's own do not.
        let message = source.to_string();
        return message
            .contains("; allowed: ")
            .then(|| RenderError::Input(format!("{} = {message}", flag(arg))));
    }
    if e.kind() != ErrorKind::InvalidValue {
        return None;
    }
    let (
        Some(ContextValue::String(arg)),
        Some(ContextValue::String(value)),
        Some(ContextValue::Strings(valid)),
    ) = (
        e.get(ContextKind::InvalidArg),
        e.get(ContextKind::InvalidValue),
        e.get(ContextKind::ValidValue),
    )
    else {
        return None;
    };
    // `--technique <TECHNIQUE>` or `[SCENE]`.
    let flag = flag(arg);
    let noun = arg.split_whitespace().nth(1).unwrap_or(flag);
    let noun = noun.trim_matches(['<', '>', '[', ']', '.']).to_lowercase();
    Some(RenderError::Input(format!(
        "{flag} = \"{value}\" is not a {noun}; allowed: {}",
        valid.join(", ")
    )))
}

/// Parses the command line, runs the subcommand and exits with its code:
/// 0 on success, 1 when a file could not be written, 2 for bad input.
pub fn run() {
    let cli = match Cli::try_parse() {
        Ok(cli) => cli,
        Err(e) => match invalid_name(&e) {
            Some(input) => exit(input),
            None => e.exit(),
        },
    };
    let result = match cli.command {
        Command::Render(a) => render::run(a),
        Command::Probe(a) => probe::run(a),
        Command::Estimate(a) => estimate::run(a),
        Command::Samples(a) => samples::run(a),
        Command::Merge(a) => merge::run(a),
        Command::DefaultScene(a) => default_scene::run(a),
    };
    if let Err(e) = result {
        exit(e);
    }
}

/// Prints `e` and exits with its code: 2 for bad input and for a reference
/// that spent its budget (the message names `--reference`), 1 when a file
/// could not be written, 130 when cancelled.
fn exit(e: RenderError) -> ! {
    eprintln!("omnee: error: {e}");
    std::process::exit(match e {
        RenderError::Input(_) | RenderError::NotConverged(_) => 2,
        RenderError::Io(_) => 1,
        RenderError::Cancelled => 130,
    });
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_command_line_is_consistent() {
        use clap::CommandFactory;
        Cli::command().debug_assert();
    }

    #[test]
    fn names_outside_their_set_are_errors_in_the_cli_form() {
        let e = Cli::try_parse_from(["omnee", "render", "--terms", "direct,glow"]).unwrap_err();
        let m = invalid_name(&e).unwrap().to_string();
        assert_eq!(
            m,
            "--terms = \"glow\" is not a term; allowed: direct, once-more, view, multiple, caustics, caustics-once-more, shafts, shafts-once-more"
        );
        let e = Cli::try_parse_from(["omnee", "default-scene", "moon"]).unwrap_err();
        let m = invalid_name(&e).unwrap().to_string();
        assert!(
            m.contains("\"moon\" is not a scene; allowed: default, underwater"),
            "{m}"
        );
        let e = Cli::try_parse_from(["omnee", "render", "--spp", "x"]).unwrap_err();
        let m = invalid_name(&e).unwrap().to_string();
        assert_eq!(m, "--spp = x is not a whole number; allowed: [1, 2^24]");
        let e = Cli::try_parse_from(["omnee", "render", "--seed", "x"]).unwrap_err();
        assert!(invalid_name(&e).is_none());
    }

    #[test]
    fn the_help_lists_every_technique_and_phase_function_with_its_description() {
        let h = after_help();
        for t in Choice::ALL {
            assert!(h.contains(&format!("  {t} ")), "{t} missing from {h}");
        }
        for k in PhaseKind::ALL {
            assert!(
                h.contains(&format!("  {} ", k.usage())),
                "{k} missing from {h}"
            );
        }
        assert!(h.contains("  hg:G                Henyey-Greenstein"), "{h}");
        assert!(h.lines().all(|l| l.len() <= 120), "{h}");
    }

    #[test]
    fn wrap_breaks_at_spaces() {
        assert_eq!(wrap("aa bb cc", 5, 2), "aa bb\n  cc");
    }
}
