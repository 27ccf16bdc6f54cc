//! Records the git commit this crate is built from as `PUSHMOG_GIT_COMMIT`, with `-dirty` when the
//! code (`src/`, `Cargo.toml`, `Cargo.lock`, this file) differs from it, so an experiment log names
//! the code that ran wherever the binary is run from; `unknown` outside a repository.

use std::path::Path;
use std::process::Command;

fn git(args: &[&str]) -> Option<String> {
    Command::new("git")
        .args(args)
        .output()
        .ok()
        .filter(|o| o.status.success())
        .map(|o| String::from_utf8_lossy(&o.stdout).trim().to_string())
}

fn main() {
    let code = ["src", "Cargo.toml", "Cargo.lock", "build.rs"];
    // A path that does not exist would make every build run this again: only existing ones.
    let mut watched: Vec<String> = code.iter().map(ToString::to_string).collect();
    if let Some(dir) = git(&["rev-parse", "--git-dir"]) {
        // A commit or a checkout moves HEAD, its branch or the index.
        watched.push(format!("{dir}/HEAD"));
        watched.push(format!("{dir}/index"));
        if let Some(branch) = git(&["symbolic-ref", "-q", "HEAD"]) {
            watched.push(format!("{dir}/{branch}"));
        }
    }
    for path in watched.iter().filter(|p| Path::new(p).exists()) {
        println!("cargo:rerun-if-changed={path}");
    }
    let commit = match git(&["rev-parse", "HEAD"]) {
        None => "unknown".to_string(),
        Some(commit) => {
            let mut args = vec!["status", "--porcelain", "--untracked-files=no", "--"];
            args.extend(code);
            match git(&args) {
                Some(changes) if !changes.is_empty() => format!("{commit}-dirty"),
                _ => commit,
            }
        }
    };
    println!("cargo:rustc-env=PUSHMOG_GIT_COMMIT={commit}");
}
