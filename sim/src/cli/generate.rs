//! `nudge generate`: families of scenarios written as TOML files, ready for `nudge batch`.

use std::process::ExitCode;

use crate::generate::{generate as draw, to_toml};
use anyhow::Context;

use super::GenerateArgs;

pub(super) fn generate(args: GenerateArgs) -> anyhow::Result<ExitCode> {
    std::fs::create_dir_all(&args.out)
        .with_context(|| format!("cannot create {}", args.out.display()))?;
    let mut written = 0;
    for family in &args.families {
        let scenarios = draw(*family, args.seed, args.count as usize)?;
        for g in &scenarios {
            let path = args.out.join(format!("{}.toml", g.scenario.name));
            let text = to_toml(g).with_context(|| format!("cannot write {}", g.scenario.name))?;
            std::fs::write(&path, text)
                .with_context(|| format!("cannot write {}", path.display()))?;
            written += 1;
        }
        println!(
            "{family}: {} scenarios ({})",
            scenarios.len(),
            family.summary()
        );
    }
    println!("{written} files in {}", args.out.display());
    Ok(ExitCode::SUCCESS)
}
