//! Parallel maps in input order, with a progress bar on a terminal.
//!
//! Inputs are computed in parallel (rayon) and delivered in input order. A streamed run
//! ([`for_each_ordered`]) computes one block of inputs at a time and hands the block's results
//! to its sink before the next block starts, so memory holds one block, not the whole run.

use indicatif::{ProgressBar, ProgressStyle};
use rayon::prelude::*;

/// How the cost of the work varies from one input to the next.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Grain {
    /// About the same small cost per input (an analytic frequency point): rayon's adaptive
    /// splitting, large streamed blocks.
    Even,
    /// Costs that differ by orders of magnitude (a simulation): inputs handed out one at a
    /// time, so one slow input does not leave a thread idle behind a coarse block.
    Uneven,
}

/// Inputs per streamed block of even work: 8192 analytic points take about 50 ms on two
/// threads and a few MB of rows, so the barrier at the end of a block costs under 1 %.
pub const EVEN_BLOCK: usize = 8192;

/// Inputs per streamed block of uneven work: a block waits for its slowest input, and 256
/// simulations (about 0.3 s to 3 s on the paper's axis) keep that wait a small part of the
/// block's time on two cores while bounding memory.
pub const UNEVEN_BLOCK: usize = 256;

impl Grain {
    fn max_len(self) -> usize {
        match self {
            Grain::Even => usize::MAX,
            Grain::Uneven => 1,
        }
    }

    fn block(self) -> usize {
        match self {
            Grain::Even => EVEN_BLOCK,
            Grain::Uneven => UNEVEN_BLOCK,
        }
    }
}

/// A progress bar on standard error, drawn only when it is a terminal (hidden otherwise, and
/// when not asked for).
#[derive(Debug, Clone)]
pub struct Progress {
    bar: ProgressBar,
}

impl Progress {
    /// A bar labelled `label` over `total` steps; `show: false` draws nothing.
    pub fn new(label: &str, total: usize, show: bool) -> Progress {
        let bar = if show {
            ProgressBar::new(total as u64)
        } else {
            ProgressBar::hidden()
        };
        let style = ProgressStyle::with_template("{prefix}: {bar:40} {pos}/{len} ({eta} left)")
            .unwrap_or_else(|_| ProgressStyle::default_bar());
        bar.set_style(style);
        bar.set_prefix(label.to_owned());
        Progress { bar }
    }

    /// Draws nothing.
    pub fn hidden() -> Progress {
        Progress::new("", 0, false)
    }

    fn tick(&self) {
        self.bar.inc(1);
    }

    /// One step done, for a run that reports its own steps (`rattle respond`'s samples).
    pub fn step(&self) {
        self.tick();
    }

    /// Clears the bar at the end of a run that reports its own steps.
    pub fn done(&self) {
        self.finish();
    }

    fn finish(&self) {
        self.bar.finish_and_clear();
    }
}

/// `work` over every input, in parallel, results in input order.
pub fn parallel_map<I, O, F>(inputs: &[I], grain: Grain, progress: &Progress, work: F) -> Vec<O>
where
    I: Sync,
    O: Send,
    F: Fn(&I) -> O + Sync + Send,
{
    let out = map_block(inputs, grain, progress, &work);
    progress.finish();
    out
}

fn map_block<I, O, F>(inputs: &[I], grain: Grain, progress: &Progress, work: &F) -> Vec<O>
where
    I: Sync,
    O: Send,
    F: Fn(&I) -> O + Sync + Send,
{
    inputs
        .par_iter()
        .with_max_len(grain.max_len())
        .map(|input| {
            let result = work(input);
            progress.tick();
            result
        })
        .collect()
}

/// `work` over every input, in parallel, each result handed to `sink` in input order as its
/// block completes (blocks of [`EVEN_BLOCK`] or [`UNEVEN_BLOCK`] inputs).
///
/// # Errors
/// The first error of `sink`; the inputs after its block are not computed.
pub fn for_each_ordered<I, O, F, S, E>(
    inputs: &[I],
    grain: Grain,
    progress: &Progress,
    work: F,
    mut sink: S,
) -> Result<(), E>
where
    I: Sync,
    O: Send,
    F: Fn(&I) -> O + Sync + Send,
    S: FnMut(O) -> Result<(), E>,
{
    for block in inputs.chunks(grain.block()) {
        for result in map_block(block, grain, progress, &work) {
            sink(result)?;
        }
    }
    progress.finish();
    Ok(())
}

/// `work` over every input, in parallel, the results handed to `sink` a block of `block`
/// inputs at a time (the last block may be shorter), blocks in input order, each as soon as
/// it is done: so that `sink` can start on the first results while the next block is
/// computed (on another thread). `block = 0` counts as 1.
pub fn for_each_block<I, O, F, S>(
    inputs: &[I],
    grain: Grain,
    block: usize,
    progress: &Progress,
    work: F,
    mut sink: S,
) where
    I: Sync,
    O: Send,
    F: Fn(&I) -> O + Sync + Send,
    S: FnMut(Vec<O>),
{
    for chunk in inputs.chunks(block.max(1)) {
        sink(map_block(chunk, grain, progress, &work));
    }
    progress.finish();
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn results_come_in_input_order() {
        let inputs: Vec<usize> = (0..20_000).collect();
        for grain in [Grain::Even, Grain::Uneven] {
            let out = parallel_map(&inputs, grain, &Progress::hidden(), |&i| i * 2);
            assert!(out.iter().enumerate().all(|(i, &o)| o == 2 * i));
            let mut streamed = Vec::new();
            for_each_ordered(
                &inputs,
                grain,
                &Progress::hidden(),
                |&i| i * 2,
                |o| {
                    streamed.push(o);
                    Ok::<(), ()>(())
                },
            )
            .unwrap();
            assert_eq!(streamed, out);
            let mut blocks = Vec::new();
            for_each_block(
                &inputs,
                grain,
                7000,
                &Progress::hidden(),
                |&i| i * 2,
                |b| blocks.push(b),
            );
            let sizes: Vec<usize> = blocks.iter().map(Vec::len).collect();
            assert_eq!(sizes, [7000, 7000, 6000]);
            assert_eq!(blocks.concat(), out);
        }
    }

    #[test]
    fn a_failing_sink_stops_the_run() {
        let inputs: Vec<usize> = (0..3 * UNEVEN_BLOCK).collect();
        let mut seen = 0;
        let r = for_each_ordered(
            &inputs,
            Grain::Uneven,
            &Progress::hidden(),
            |&i| i,
            |i| {
                seen += 1;
                if i == 10 {
                    Err("stop")
                } else {
                    Ok(())
                }
            },
        );
        assert_eq!(r, Err("stop"));
        assert_eq!(seen, 11);
    }
}
