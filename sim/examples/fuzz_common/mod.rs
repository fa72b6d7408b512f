//! The loop the seeded mutation fuzzers share: make each input, judge it with its time taken, save
//! and count what is a finding (a panic, a misjudged input, or one slower than the hang limit), and
//! sum up.

use std::any::Any;
use std::panic::{AssertUnwindSafe, catch_unwind};
use std::time::{Duration, Instant};

/// What one input did.
pub enum Judged {
    /// Accepted (loaded, read, parsed) as it should be.
    Accepted,
    /// Refused with an error as it should be.
    Refused,
    /// A finding, and why.
    Finding(String),
}

/// What a whole run of the loop found.
pub struct Tally {
    /// Inputs accepted.
    pub accepted: u64,
    /// Inputs refused with an error.
    pub refused: u64,
    /// Findings.
    pub findings: u64,
    /// The slowest input's time.
    pub slowest: Duration,
    /// The loop's wall time.
    pub wall: Duration,
}

/// Runs `inputs` inputs: `make` builds input `i`, `judge` says what it did (given `i` too), and
/// every finding (a slow input included: over `slow`) is passed to `save` with why, printed to
/// stderr and counted.
/// Panics inside `judge` should be caught with [`caught`]; the default panic hook is silenced here.
pub fn drive<I>(
    inputs: u64,
    slow: Duration,
    mut make: impl FnMut(u64) -> I,
    mut judge: impl FnMut(u64, &I) -> Judged,
    mut save: impl FnMut(u64, &I, &str),
) -> Tally {
    // Panics are caught and counted; the default hook would print each one.
    std::panic::set_hook(Box::new(|_| {}));
    let started = Instant::now();
    let mut tally = Tally {
        accepted: 0,
        refused: 0,
        findings: 0,
        slowest: Duration::ZERO,
        wall: Duration::ZERO,
    };
    for i in 0..inputs {
        let input = make(i);
        let t0 = Instant::now();
        let judged = judge(i, &input);
        let took = t0.elapsed();
        tally.slowest = tally.slowest.max(took);
        let finding = match judged {
            Judged::Accepted => {
                tally.accepted += 1;
                None
            }
            Judged::Refused => {
                tally.refused += 1;
                None
            }
            Judged::Finding(why) => Some(why),
        }
        .or_else(|| (took > slow).then(|| format!("slow: {} ms", took.as_millis())));
        if let Some(why) = finding {
            tally.findings += 1;
            save(i, &input, &why);
            eprintln!("input {i}: {why}");
        }
    }
    tally.wall = started.elapsed();
    tally
}

impl Tally {
    /// Prints the run's summary line: `inputs` inputs of `seed`, the accepted and refused counted
    /// under the fuzzer's own words for them.
    pub fn print(&self, inputs: u64, seed: u64, accepted: &str, refused: &str) {
        let wall = self.wall.as_secs_f64();
        println!(
            "{inputs} inputs (seed {seed}): {} {accepted}, {} {refused}, {} findings; slowest {:.1} ms; {wall:.1} s ({:.0} inputs/s)",
            self.accepted,
            self.refused,
            self.findings,
            self.slowest.as_secs_f64() * 1e3,
            inputs as f64 / wall.max(1e-9),
        );
    }

    /// Success when nothing was found.
    pub fn exit_code(&self) -> std::process::ExitCode {
        if self.findings == 0 {
            std::process::ExitCode::SUCCESS
        } else {
            std::process::ExitCode::FAILURE
        }
    }
}

/// Runs `f`, catching a panic as its message.
pub fn caught<T>(f: impl FnOnce() -> T) -> Result<T, String> {
    catch_unwind(AssertUnwindSafe(f)).map_err(|payload| panic_message(payload.as_ref()))
}

/// A panic's message, whatever its payload.
fn panic_message(payload: &(dyn Any + Send)) -> String {
    payload
        .downcast_ref::<String>()
        .cloned()
        .or_else(|| payload.downcast_ref::<&str>().map(|s| (*s).to_owned()))
        .unwrap_or_else(|| "a panic without a message".into())
}
