//! Benchmarks (issue 2's `viscosph bench`; extended by issue 6).

use clap::Args;

#[derive(Args, Debug)]
pub struct BenchArgs {
    /// Output directory.
    #[arg(long, default_value = "results/bench")]
    pub out: std::path::PathBuf,
}

pub fn main(_args: BenchArgs) -> Result<(), Box<dyn std::error::Error>> {
    Err("bench: not built yet".into())
}
