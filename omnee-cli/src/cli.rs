//! The command line in one place: the subcommands, clap's parsing (with
//! errors about closed sets of names in the CLI's own form), and the
//! dispatch to each subcommand's `run` in [`crate::commands`].

use crate::commands::default_scene::{self, DefaultSceneArgs};
use crate::commands::estimate::{self, EstimateArgs};
use crate::commands::merge::{self, MergeArgs};
use crate::commands::probe::{self, ProbeArgs};
use crate::commands::render::{self, RenderArgs};
use crate::commands::samples::{self, SamplesArgs};
use crate::error::CliError;
use crate::technique::Technique;
use clap::error::{ContextKind, ContextValue, ErrorKind};
use clap::{Parser, Subcommand, ValueEnum};

const PHASE_SPECS: &str = "\
Phase function specs (scene files' medium.phase and --phase):
  iso                 isotropic, p = 1/(4 pi)
  hg:G                Henyey-Greenstein, G in (-1, 1) (G > 0: forward)
  tthg:G1,G2,W        two-term HG, W*HG(G1) + (1-W)*HG(G2); G1, G2 in (-1, 1), W in [0, 1]
  ff:B,N              Fournier-Forand, backscatter fraction B in (0, 0.5), refractive index N in [1.001, 1.5]
  draine:G,ALPHA      Draine, G in (-1, 1), ALPHA in [0, 1000]
  mie:DIAMETER_UM     approximate Mie (Jendersie & d'Eon 2023), droplet diameter in (0, 50] micrometres
  rayleigh            Rayleigh, p = 3/(16 pi) (1 + cos^2)
  table:FILE.csv      measured: lines 'angle_deg,value', angles increasing in [0, 180]
Angles are deflections between propagation directions (0 = straight on).";

const EXIT_CODES: &str = "\
Exit codes: 0 success, 1 a file could not be written, 2 bad input (the message names
the field, its value and the allowed range).";

/// The text after the options: the phase specs, the techniques (from
/// [`Technique`]'s documentation) and the exit codes.
fn after_help() -> String {
    let techniques: Vec<String> = Technique::value_variants()
        .iter()
        .filter_map(ValueEnum::to_possible_value)
        .map(|v| {
            let help = v.get_help().map(|h| h.to_string()).unwrap_or_default();
            format!("  {:<12} {}", v.get_name(), wrap(&help, 80, 15))
        })
        .collect();
    format!(
        "{PHASE_SPECS}\n\nTechniques for the once-more term (--technique):\n{}\n\n{EXIT_CODES}",
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

/// A clap error about a value outside a closed set of names, in the CLI's
/// form: `--technique = "magic" is not a technique; allowed: omnee, ...`
/// (the noun is the option's value name).
fn invalid_name(e: &clap::Error) -> Option<CliError> {
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
    let mut parts = arg.split_whitespace();
    let flag = parts.next().unwrap_or(arg);
    let noun = parts.next().unwrap_or(flag);
    let noun = noun.trim_matches(['<', '>', '[', ']', '.']).to_lowercase();
    Some(CliError::Input(format!(
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

/// Prints `e` and exits with its code.
fn exit(e: CliError) -> ! {
    eprintln!("omnee: error: {e}");
    std::process::exit(e.exit_code());
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
            "--terms = \"glow\" is not a term; allowed: direct, once-more, view, caustics, caustics-once-more, shafts, shafts-once-more"
        );
        let e = Cli::try_parse_from(["omnee", "default-scene", "moon"]).unwrap_err();
        let m = invalid_name(&e).unwrap().to_string();
        assert!(
            m.contains("\"moon\" is not a scene; allowed: default, underwater"),
            "{m}"
        );
        let e = Cli::try_parse_from(["omnee", "render", "--spp", "x"]).unwrap_err();
        assert!(invalid_name(&e).is_none());
    }

    #[test]
    fn the_help_lists_every_technique_with_its_description() {
        let h = after_help();
        for t in Technique::value_variants() {
            assert!(h.contains(&format!("  {t} ")), "{t} missing from {h}");
        }
        assert!(h.lines().all(|l| l.len() <= 120), "{h}");
    }

    #[test]
    fn wrap_breaks_at_spaces() {
        assert_eq!(wrap("aa bb cc", 5, 2), "aa bb\n  cc");
    }
}
