//! Per-pass timers: where the time of a step goes, wall clock and CPU, and which parts of a step
//! run on one thread (the serial share that bounds the speed-up on more cores, Amdahl's law).
//!
//! Off by default: a scheme asks [`Profile::start`] for a clock reading only when profiling is on,
//! so a run that does not profile executes no timer code (the instruction counts of the
//! throughput benchmarks stay those of the solver alone). CPU time is the process's (every
//! thread, rayon's idle workers spinning included) from `CLOCK_PROCESS_CPUTIME_ID` on Unix; 0 on
//! other platforms.

/// A clock reading: wall time and the process's CPU time.
#[derive(Debug, Clone, Copy)]
pub struct Stamp {
    wall: std::time::Instant,
    cpu: f64,
}

impl Stamp {
    /// Now.
    pub fn now() -> Self {
        Self {
            wall: std::time::Instant::now(),
            cpu: process_cpu_seconds(),
        }
    }

    /// Wall and CPU seconds since this reading.
    pub fn elapsed(&self) -> (f64, f64) {
        let now = Self::now();
        ((now.wall - self.wall).as_secs_f64(), now.cpu - self.cpu)
    }
}

/// CPU seconds the process has used so far, all threads (0 where not available).
pub fn process_cpu_seconds() -> f64 {
    #[cfg(unix)]
    {
        let mut ts = libc::timespec {
            tv_sec: 0,
            tv_nsec: 0,
        };
        // SAFETY: a valid pointer to a timespec; the clock id is a constant every Unix has.
        let rc = unsafe { libc::clock_gettime(libc::CLOCK_PROCESS_CPUTIME_ID, &mut ts) };
        if rc == 0 {
            return ts.tv_sec as f64 + 1e-9 * ts.tv_nsec as f64;
        }
        0.0
    }
    #[cfg(not(unix))]
    {
        0.0
    }
}

/// The time of one named part of a step, summed over the steps.
#[derive(Debug, Clone, PartialEq)]
pub struct PassTime {
    pub name: &'static str,
    /// Wall-clock seconds.
    pub wall: f64,
    /// CPU seconds of the whole process while the part ran.
    pub cpu: f64,
    /// Whether the part runs on one thread (its wall time does not shrink with more threads).
    pub serial: bool,
}

/// Where the time of the steps went: per part, and in total.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Timings {
    /// Wall seconds of the steps, every part included.
    pub total: f64,
    /// CPU seconds of the steps.
    pub total_cpu: f64,
    /// Steps timed.
    pub steps: u64,
    /// The parts, in the order they first ran.
    pub parts: Vec<PassTime>,
}

impl Timings {
    /// Wall seconds spent in the part called `name` (0 if not timed).
    pub fn part(&self, name: &str) -> f64 {
        self.parts
            .iter()
            .find(|p| p.name == name)
            .map_or(0.0, |p| p.wall)
    }

    /// The share of the step's time spent in the part called `name`: of the CPU time where
    /// every part has one (as [`Timings::serial_share`]), else of the wall time (0 if not
    /// timed).
    pub fn share(&self, name: &str) -> f64 {
        let Some(p) = self.parts.iter().find(|p| p.name == name) else {
            return 0.0;
        };
        if self.by_cpu() {
            p.cpu / self.total_cpu
        } else {
            p.wall / self.total.max(f64::MIN_POSITIVE)
        }
    }

    /// Whether shares are of the CPU time: the platform has a CPU clock and every part that
    /// took time has its CPU time.
    fn by_cpu(&self) -> bool {
        self.total_cpu > 0.0 && self.parts.iter().all(|p| p.cpu > 0.0 || p.wall == 0.0)
    }

    /// Wall seconds of the parts that run on one thread.
    pub fn serial_wall(&self) -> f64 {
        self.parts.iter().filter(|p| p.serial).map(|p| p.wall).sum()
    }

    /// Wall seconds of the step not inside any timed part (bookkeeping between the parts).
    pub fn untimed_wall(&self) -> f64 {
        (self.total - self.parts.iter().map(|p| p.wall).sum::<f64>()).max(0.0)
    }

    /// The serial share of a step: the time of the serial parts and of the untimed rest (which
    /// runs on one thread) over the total. In CPU time where the platform has it: on one thread
    /// that is the work itself, while the wall clock also counts the time other processes hold
    /// the core (on a loaded machine, most of it); from a run on one thread, this is Amdahl's s.
    pub fn serial_share(&self) -> f64 {
        // CPU time per part only if every part has it (a scheme's timings kept without the
        // profile, such as ISPH's solves' wall clock, have none).
        if self.by_cpu() {
            let timed: f64 = self.parts.iter().map(|p| p.cpu).sum();
            let serial: f64 = self.parts.iter().filter(|p| p.serial).map(|p| p.cpu).sum();
            ((serial + (self.total_cpu - timed).max(0.0)) / self.total_cpu).min(1.0)
        } else if self.total > 0.0 {
            ((self.serial_wall() + self.untimed_wall()) / self.total).min(1.0)
        } else {
            0.0
        }
    }

    /// Add `wall` and `cpu` seconds to the part `name`.
    pub fn add(&mut self, name: &'static str, serial: bool, wall: f64, cpu: f64) {
        match self.parts.iter_mut().find(|p| p.name == name) {
            Some(p) => {
                p.wall += wall;
                p.cpu += cpu;
            }
            None => self.parts.push(PassTime {
                name,
                wall,
                cpu,
                serial,
            }),
        }
    }

    /// What was timed after `earlier` (an earlier reading of the same timers), part by part.
    pub fn since(&self, earlier: &Timings) -> Timings {
        let mut t = Timings {
            total: self.total - earlier.total,
            total_cpu: self.total_cpu - earlier.total_cpu,
            steps: self.steps - earlier.steps.min(self.steps),
            parts: Vec::new(),
        };
        for p in &self.parts {
            let before = earlier.parts.iter().find(|q| q.name == p.name);
            t.add(
                p.name,
                p.serial,
                p.wall - before.map_or(0.0, |q| q.wall),
                p.cpu - before.map_or(0.0, |q| q.cpu),
            );
        }
        t
    }

    /// Sum of `self` and `other`, part by part.
    pub fn merged(mut self, other: &Timings) -> Timings {
        self.total += other.total;
        self.total_cpu += other.total_cpu;
        self.steps = self.steps.max(other.steps);
        for p in &other.parts {
            self.add(p.name, p.serial, p.wall, p.cpu);
        }
        self
    }

    /// A plain-text table: per part wall and CPU seconds, share of the step, CPU over wall (the
    /// threads busy on average) and whether it is serial.
    pub fn table(&self) -> String {
        let mut s = format!(
            "{:<38} {:>10} {:>10} {:>7} {:>8}  {}\n",
            "part", "wall [s]", "CPU [s]", "share", "CPU/wall", "runs on"
        );
        // Shares of the CPU time where every part has one (see `serial_share`), else of the
        // wall time.
        let by_cpu = self.by_cpu();
        let row = |name: &str, wall: f64, cpu: f64, serial: Option<bool>| {
            format!(
                "{:<38} {:>10.4} {:>10.4} {:>6.2}% {:>8.2}  {}\n",
                name,
                wall,
                cpu,
                if by_cpu {
                    100.0 * cpu / self.total_cpu
                } else {
                    100.0 * wall / self.total.max(f64::MIN_POSITIVE)
                },
                if wall > 0.0 { cpu / wall } else { 0.0 },
                match serial {
                    Some(true) => "one thread",
                    Some(false) => "all threads",
                    None => "",
                }
            )
        };
        for p in &self.parts {
            s += &row(p.name, p.wall, p.cpu, Some(p.serial));
        }
        let timed_cpu: f64 = self.parts.iter().map(|p| p.cpu).sum();
        s += &row(
            "(between the parts)",
            self.untimed_wall(),
            (self.total_cpu - timed_cpu).max(0.0),
            Some(true),
        );
        s += &row(
            &format!("step ({} steps)", self.steps),
            self.total,
            self.total_cpu,
            None,
        );
        s += &format!(
            "serial share of a step: {:.2}%\n",
            100.0 * self.serial_share()
        );
        s
    }
}

/// Amdahl's law: the parallel efficiency on `threads` threads of work whose serial share is
/// `serial` (at one thread).
pub fn amdahl_efficiency(serial: f64, threads: usize) -> f64 {
    let p = threads as f64;
    1.0 / (serial + (1.0 - serial) / p) / p
}

/// The timers of a scheme: None while profiling is off.
#[derive(Debug, Clone, Default)]
pub struct Profile(Option<Timings>);

impl Profile {
    /// Turn timing on (keeping what was timed) or off.
    pub fn enable(&mut self, on: bool) {
        if on {
            self.0.get_or_insert_with(Timings::default);
        } else {
            self.0 = None;
        }
    }

    /// A clock reading if profiling is on.
    #[inline]
    pub fn start(&self) -> Option<Stamp> {
        self.0.as_ref().map(|_| Stamp::now())
    }

    /// Book the time since `since` to part `name` and return a new reading (the start of the
    /// next part).
    #[inline]
    pub fn lap(&mut self, since: Option<Stamp>, name: &'static str, serial: bool) -> Option<Stamp> {
        let (t, since) = (self.0.as_mut()?, since?);
        let now = Stamp::now();
        t.add(
            name,
            serial,
            (now.wall - since.wall).as_secs_f64(),
            now.cpu - since.cpu,
        );
        Some(now)
    }

    /// Book a whole step that began at `since`.
    #[inline]
    pub fn step(&mut self, since: Option<Stamp>) {
        if let (Some(t), Some(since)) = (self.0.as_mut(), since) {
            let now = Stamp::now();
            t.total += (now.wall - since.wall).as_secs_f64();
            t.total_cpu += now.cpu - since.cpu;
            t.steps += 1;
        }
    }

    /// What was timed so far (empty while off).
    pub fn timings(&self) -> Timings {
        self.0.clone().unwrap_or_default()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parts_add_up_and_serial_share_counts_the_untimed_rest() {
        let mut t = Timings {
            total: 10.0,
            total_cpu: 18.0,
            steps: 4,
            parts: Vec::new(),
        };
        t.add("a", false, 6.0, 12.0);
        t.add("b", true, 2.0, 2.0);
        t.add("a", false, 1.0, 2.0);
        assert_eq!(t.part("a"), 7.0);
        assert_eq!(t.untimed_wall(), 1.0);
        // In CPU time: serial 2 s and the untimed 18 - 16 = 2 s of 18 s.
        assert!((t.serial_share() - 4.0 / 18.0).abs() < 1e-15);
        assert!(t.table().contains("serial share of a step: 22.22%"));
        // Without a CPU clock, in wall time: (2 + 1) / 10.
        t.total_cpu = 0.0;
        assert!((t.serial_share() - 0.3).abs() < 1e-15);
    }

    #[test]
    fn since_subtracts_part_by_part_and_a_part_without_cpu_falls_back_to_wall() {
        let mut a = Timings::default();
        a.add("solve", false, 1.0, 0.0);
        let mut b = a.clone();
        b.total = 4.0;
        b.total_cpu = 4.0;
        b.add("solve", false, 2.0, 0.0);
        b.add("rest", true, 1.0, 1.0);
        let d = b.since(&a);
        assert_eq!((d.part("solve"), d.part("rest")), (2.0, 1.0));
        // "solve" has no CPU time: the share is in wall time, (1 + untimed 1) / 4.
        assert!((d.serial_share() - 0.5).abs() < 1e-15);
    }

    #[test]
    fn amdahl_bounds() {
        assert!((amdahl_efficiency(0.0, 16) - 1.0).abs() < 1e-15);
        // 2 % serial: 16 threads give 1 / (0.02 + 0.98 / 16) = 12.3x, 76.9 %.
        assert!((amdahl_efficiency(0.02, 16) - 0.7692).abs() < 1e-4);
        assert!((amdahl_efficiency(1.0, 8) - 0.125).abs() < 1e-15);
    }

    #[test]
    fn off_times_nothing() {
        let mut p = Profile::default();
        assert!(p.start().is_none());
        p.step(p.start());
        assert_eq!(p.timings(), Timings::default());
        p.enable(true);
        let s = p.start();
        let s = p.lap(s, "x", true);
        p.step(s);
        let t = p.timings();
        assert_eq!((t.steps, t.parts.len()), (1, 1));
        assert!(t.total >= 0.0 && process_cpu_seconds() > 0.0);
    }
}
