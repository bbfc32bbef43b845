//! The `areo` command line: parse flags, call areo-scenario, print what it returns
//! (`print`), map errors to exit codes (0 success, 1 failure while running, 2 bad
//! input: flags, scenario files, times; 3 unreachable goals; 4 searches stopped by the
//! work or memory budget; 141 when standard output's reader has gone, see `console`).
//! It computes nothing.

use std::io::IsTerminal;
use std::path::PathBuf;
use std::process::ExitCode;

mod console;
mod print;

use areo_scenario::budget::{Budget, DemCommand};
use areo_scenario::{Error, Failure, Progress};
use clap::{Args, CommandFactory, Parser, Subcommand, ValueEnum};
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};

/// Plans what a planetary rover should do: TEMPEST long-range planning in position,
/// time and energy, and physics-based action planning for the LSR-1 rover.
#[derive(Debug, Parser)]
#[command(name = "areo", version, about, long_about = None)]
struct Cli {
    /// More log output (-v info, -vv debug, -vvv trace).
    #[arg(short, long, action = clap::ArgAction::Count, global = true)]
    verbose: u8,
    /// Only errors.
    #[arg(short, long, global = true, conflicts_with = "verbose")]
    quiet: bool,
    /// Refuse a job whose estimated peak memory exceeds this, GiB (default: three
    /// quarters of this machine's memory).
    #[arg(long, global = true, value_name = "GIB")]
    max_memory_gb: Option<f64>,
    /// Refuse a job whose estimated work exceeds this many elementary steps (module
    /// executions, cell-sector rays; a search's label expansion counts 100), and stop
    /// its searches there (default 2e10, 10–40 minutes of work).
    #[arg(long, global = true, value_name = "STEPS")]
    max_work: Option<f64>,
    #[command(subcommand)]
    command: Command,
}

#[derive(Debug, Subcommand)]
enum Command {
    /// Run a scenario file and write its outputs to OUT/NAME/.
    Run {
        /// The scenario (RON), e.g. scenarios/gale-sol-sun.ron.
        scenario: PathBuf,
        /// Output directory; files go to OUT/NAME/ where NAME is the scenario's file stem.
        #[arg(short, long, default_value = "out")]
        out: PathBuf,
        /// Replace a field of the scenario before running, as a sweep's axis does:
        /// PATH=VALUE with PATH dotted (`job.tau`, `job.goals[1].x_m`) and VALUE in RON
        /// (0.6, "2012-08-06T22:15:00Z"); the field must be written in the file.
        /// Repeatable.
        #[arg(long = "set", value_name = "PATH=VALUE")]
        set: Vec<String>,
        /// Print the summary, facts and files as JSON instead of text.
        #[arg(long)]
        json: bool,
    },
    /// Solve Moving AI grid benchmark scenarios with the ISE (8-connected, no corner
    /// cutting); prints `index,expected,found,expansions` per scenario and
    /// `N solved, M mismatched`.
    Grid(GridArgs),
    /// DEM tools: information, slope, shadows, horizon maps, viewsheds (GeoTIFF, ESRI
    /// ASCII, PDS3).
    #[command(subcommand)]
    Terrain(TerrainCommand),
    /// Where the Sun is: at one instant, at instants listed in a file, or the rise, noon
    /// and set of a sol at a site.
    Sun(SunArgs),
    /// Rover models: check a parameter file.
    #[command(subcommand)]
    Rover(RoverCommand),
    /// Studies as sweeps: expand a sweep file into array tasks, run one, collect them,
    /// or print a Slurm or Kubernetes launch recipe.
    #[command(subcommand)]
    Sweep(SweepCommand),
    /// Print a shell completion script, e.g. `areo completions bash >
    /// ~/.local/share/bash-completion/completions/areo`.
    Completions {
        /// The shell.
        shell: clap_complete::Shell,
    },
}

#[derive(Debug, Subcommand)]
enum SweepCommand {
    /// Write one validated scenario per task and the manifest into DIR.
    Expand {
        /// The sweep file (RON), e.g. scenarios/sweeps/landing-date.sweep.ron.
        sweep: PathBuf,
        /// The sweep directory.
        #[arg(short = 'o', long)]
        out: PathBuf,
        /// Replace another sweep's expansion (and its outputs) in the directory.
        #[arg(long)]
        force: bool,
    },
    /// Run one task into DIR/out/ID/ (skipped if finished, unless --force).
    Run {
        /// The sweep directory.
        dir: PathBuf,
        /// The task; default SLURM_ARRAY_TASK_ID, then JOB_COMPLETION_INDEX.
        #[arg(long)]
        index: Option<usize>,
        /// Run a finished task again.
        #[arg(long)]
        force: bool,
    },
    /// Merge the finished tasks' facts into DIR/results.csv; list missing and failed.
    Collect {
        /// The sweep directory.
        dir: PathBuf,
        /// Plot this fact against --against.
        #[arg(long, requires = "against")]
        plot: Option<String>,
        /// The axis to plot against.
        #[arg(long, requires = "plot")]
        against: Option<String>,
    },
    /// Print an sbatch script running the sweep as a Slurm job array.
    Slurm {
        /// The sweep directory.
        dir: PathBuf,
        /// Tasks at once (`%K` of --array).
        #[arg(long, default_value_t = 8)]
        parallel: usize,
        /// Cores per task.
        #[arg(long, default_value_t = 2)]
        cpus: usize,
    },
    /// Print a Kubernetes Indexed Job running the sweep.
    K8s {
        /// The sweep directory (mounted at the same path in the pods).
        dir: PathBuf,
        /// The container image holding the areo binary.
        #[arg(long, default_value = "areo:latest")]
        image: String,
        /// The persistent volume claim holding the sweep directory.
        #[arg(long, default_value = "areo-sweeps")]
        claim: String,
        /// Pods at once.
        #[arg(long, default_value_t = 8)]
        parallel: usize,
    },
}

#[derive(Debug, Subcommand)]
enum RoverCommand {
    /// Pose, wheel loads and torques, binding limits, stability margin and the smallest
    /// friction that holds, for a parameter file on a test terrain; for a TEMPEST
    /// resource model, drive power and Wh per km on flat ground and slopes, the array's
    /// output per W/m², and how long a full battery lasts.
    Check {
        /// Rover parameters (RON), e.g. crates/rover/params/lsr1.ron, or a resource
        /// model, e.g. scenarios/rovers/mock-solar-rover.ron (only --terrain flat or
        /// slope:DEG and --format apply to it).
        params: PathBuf,
        /// flat, slope:DEG (rising ahead), side-slope:DEG (rising to the left), or
        /// step:HEIGHT_M (front wheels against a vertical step).
        #[arg(long, default_value = "flat", value_parser = clap::value_parser!(areo_scenario::rover_check::TestTerrain))]
        terrain: areo_scenario::rover_check::TestTerrain,
        /// Wheel–ground friction coefficient.
        #[arg(long, default_value_t = 0.6)]
        mu: f64,
        /// Driving forward (rolling resistance counts) rather than holding still.
        #[arg(long)]
        moving: bool,
        /// Output format.
        #[arg(long, value_enum, default_value_t = ReportFormat::Text)]
        format: ReportFormat,
        /// For a resource model without `gravity_m_s2`: whose gravity it drives in.
        #[arg(long, value_enum, default_value_t = BodyArg::Mars)]
        body: BodyArg,
    },
}

/// `areo terrain shadow --method`.
#[derive(Debug, Clone, Copy, ValueEnum)]
enum ShadowMethodArg {
    OwnRay,
    Sheared,
    Interpolated,
}

impl From<ShadowMethodArg> for areo_scenario::terrain::ShadowMethod {
    fn from(m: ShadowMethodArg) -> Self {
        match m {
            ShadowMethodArg::OwnRay => Self::OwnRay,
            ShadowMethodArg::Sheared => Self::Sheared,
            ShadowMethodArg::Interpolated => Self::Interpolated,
        }
    }
}

#[derive(Debug, Clone, Copy, ValueEnum)]
enum ReportFormat {
    Text,
    Json,
}

/// A body of `areo sun --body`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
enum BodyArg {
    Mars,
    Moon,
    Earth,
}

impl BodyArg {
    fn body(self) -> areo_scenario::Body {
        match self {
            BodyArg::Mars => areo_scenario::Body::Mars,
            BodyArg::Moon => areo_scenario::Body::Moon,
            BodyArg::Earth => areo_scenario::Body::Earth,
        }
    }
}

#[derive(Debug, Args)]
#[command(group = clap::ArgGroup::new("when").required(true).args(["time", "times_file", "sol", "mission_sol", "day", "from"]))]
struct SunArgs {
    /// An instant, UTC: ISO 8601 (2012-08-06T05:17:57Z), day of year
    /// (2012-219T05:17:57) or SPICE's form ("2012 AUG 06 05:17:57").
    #[arg(long)]
    time: Option<String>,
    /// A file of UTC instants, one per line (`-`: standard input).
    #[arg(long)]
    times_file: Option<PathBuf>,
    /// Every --step from this instant (UTC) to --to.
    #[arg(long, requires_all = ["to", "step"])]
    from: Option<String>,
    /// The last instant of a --from range (UTC).
    #[arg(long, requires = "from")]
    to: Option<String>,
    /// The step of a --from range: a number and a unit (30s, 10min, 1h, 1d, 1sol).
    #[arg(long, requires = "from")]
    step: Option<String>,
    /// A local sol number at the site (the Mars Sol Date counted in local mean time,
    /// e.g. 49269 for the sol Curiosity landed in): prints sunrise, noon and sunset.
    /// For a mission's own count give --landing and --mission-sol. Needs --lat and
    /// --lon.
    #[arg(long, requires_all = ["lat", "lon"])]
    sol: Option<i64>,
    /// A mission sol: sol 0 is the local sol of --landing at the site (so
    /// `--landing 2012-08-06T05:17:57Z --mission-sol 100` is Curiosity's sol 100).
    /// Needs --landing, --lat and --lon.
    #[arg(long, requires_all = ["landing", "lat", "lon"], allow_hyphen_values = true)]
    mission_sol: Option<i64>,
    /// The landing instant (UTC) that --mission-sol counts from.
    #[arg(long, requires = "mission_sol")]
    landing: Option<String>,
    /// On the Moon or the Earth: the solar day from this date (YYYY-MM-DD, 00:00 UTC;
    /// a synodic month on the Moon): sunrises, sunsets, the Sun's highest point,
    /// daylight hours (and on the Moon the Earth's). Needs --lat and --lon.
    #[arg(long, requires_all = ["lat", "lon"])]
    day: Option<String>,
    /// Whose sky: mars (Mars24), moon (Sun and Earth from a lunar site) or earth (the
    /// Sun at a WGS84 site, UTC as UT1).
    #[arg(long, value_enum, default_value_t = BodyArg::Mars)]
    body: BodyArg,
    /// Site latitude, degrees: planetocentric on Mars and the Moon, geodetic on the Earth.
    #[arg(long, requires = "lon", allow_hyphen_values = true)]
    lat: Option<f64>,
    /// Site longitude, degrees east.
    #[arg(long, requires = "lat", allow_hyphen_values = true)]
    lon: Option<f64>,
    /// Output format.
    #[arg(long, value_enum, default_value_t = Format::Text)]
    format: Format,
}

#[derive(Debug, Subcommand)]
enum TerrainCommand {
    /// Size, cell size, extent, elevation range and georeference of a DEM.
    Info {
        /// The DEM (.tif, .asc, .img/.lbl).
        file: PathBuf,
        /// Print JSON (plain names and units) instead of text.
        #[arg(long)]
        json: bool,
    },
    /// Slope in degrees (float32 GeoTIFF) by Horn's method, and a hillshade PNG beside it.
    Slope {
        /// The DEM.
        file: PathBuf,
        /// Output GeoTIFF.
        #[arg(short, long)]
        out: PathBuf,
    },
    /// Direct sun for a Sun direction (uint8 GeoTIFF: 1 lit, 0 shadowed, 255 no data),
    /// and a PNG preview beside it.
    Shadow {
        /// The DEM.
        file: PathBuf,
        /// Sun azimuth, degrees clockwise from north.
        #[arg(long, allow_hyphen_values = true, required_unless_present = "utc", requires = "sun_elevation")]
        sun_azimuth: Option<f64>,
        /// Sun elevation above the local horizontal, degrees.
        #[arg(long, allow_hyphen_values = true, required_unless_present = "utc", requires = "sun_azimuth")]
        sun_elevation: Option<f64>,
        /// Instead of a direction: the Sun of this instant (UTC) over the map's middle,
        /// on the body its georeference names (Mars24, the lunar or the terrestrial
        /// ephemeris).
        #[arg(long, conflicts_with_all = ["sun_azimuth", "sun_elevation"])]
        utc: Option<String>,
        /// Ignore planetary curvature (otherwise the radius of the DEM's body is used).
        #[arg(long)]
        flat: bool,
        /// How each cell's cast shadow is decided: own-ray (each cell by its own ray to
        /// the Sun on the DEM's triangulated surface, as a brute-force ray cast does),
        /// sheared (rays beside a cell lend it their occluders; approximate off the cardinal
        /// azimuths: up to 0.25 % of cells differ at a Sun 5° up or more), interpolated (the
        /// cheapest, on a coarser
        /// surface: up to 0.5 % differ, within a degree of grazing). The map also
        /// darkens cells whose slope faces away from the Sun.
        #[arg(long, value_enum, default_value_t = ShadowMethodArg::OwnRay)]
        method: ShadowMethodArg,
        /// For DEMs too large to hold (metre-scale DTMs): compute the map tile by tile,
        /// TILE × TILE cells each, reading a GeoTIFF a window at a time with the halo
        /// its longest shadow needs (stated), and write it as a tiled GeoTIFF (TILE a multiple of 16; BigTIFF past
        /// 4 GB). No PNG preview. With own-ray, the same map as without.
        #[arg(long, value_name = "TILE", value_parser = clap::value_parser!(u32).range(16..=65536))]
        tile: Option<u32>,
        /// Output GeoTIFF.
        #[arg(short, long)]
        out: PathBuf,
    },
    /// What a point above the ground sees (uint8 GeoTIFF: 1 visible, 0 hidden, 255 no
    /// data), by ray casts with planetary curvature, and a PNG preview beside it.
    Viewshed {
        /// The DEM.
        file: PathBuf,
        /// Observer: map x and y (m, the DEM's frame) and height above the ground (m),
        /// as X,Y,HEIGHT.
        #[arg(long, value_parser = parse_xyz, allow_hyphen_values = true)]
        from: (f64, f64, f64),
        /// Output GeoTIFF.
        #[arg(short, long)]
        out: PathBuf,
    },
    /// Horizon elevation in K azimuth sectors (one float32 GeoTIFF per sector; with
    /// --tile, one tiled GeoTIFF with a plane per sector).
    Horizon {
        /// The DEM.
        file: PathBuf,
        /// Number of sectors, 16..=360.
        #[arg(long, default_value_t = 64, value_parser = clap::value_parser!(u16).range(16..=360))]
        sectors: u16,
        /// For DEMs too large to hold: compute the map tile by tile (TILE × TILE cells,
        /// a multiple of 16), each read with the halo its lowest Sun needs (stated), and
        /// write ONE tiled GeoTIFF to OUT: uint16 codes, a plane per sector (degrees =
        /// code × 180/65535 − 90, written as GDAL band scale and offset).
        #[arg(long, value_name = "TILE", value_parser = clap::value_parser!(u32).range(16..=65536))]
        tile: Option<u32>,
        /// With --tile: the lowest Sun the map must answer for, degrees; lower horizons
        /// are stored as it (the halo is relief / tan of it).
        #[arg(long, value_name = "DEG", default_value_t = 5.0)]
        lowest_sun: f64,
        /// Output directory (one GeoTIFF per sector: OUT/s000.tif …, replaced whole), or
        /// with --tile the output GeoTIFF.
        #[arg(short, long)]
        out: PathBuf,
    },
}

#[derive(Debug, Args)]
struct GridArgs {
    /// The map (Moving AI `.map`).
    #[arg(long)]
    map: PathBuf,
    /// The scenarios (Moving AI `.scen`).
    #[arg(long)]
    scen: PathBuf,
    /// Output format.
    #[arg(long, value_enum, default_value_t = Format::Text)]
    format: Format,
    /// Also block K random free cells within 2 cells of each start, re-plan
    /// incrementally, and check the result against a fresh search.
    #[arg(long, value_name = "K")]
    replan: Option<u32>,
    /// Seed for --replan's cells.
    #[arg(long, default_value_t = 0)]
    seed: u64,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub(crate) enum Format {
    Text,
    Json,
    Csv,
}

/// `--quiet`: no progress bars either.
static QUIET: std::sync::atomic::AtomicBool = std::sync::atomic::AtomicBool::new(false);

fn main() -> ExitCode {
    // A write past the file-size limit (`ulimit -f`) would end the process by SIGXFSZ,
    // silently; caught, the write fails with EFBIG and the error names the file.
    let _ = signal_hook::flag::register(
        signal_hook::consts::SIGXFSZ,
        std::sync::Arc::new(std::sync::atomic::AtomicBool::new(false)),
    );
    let cli = Cli::parse();
    QUIET.store(cli.quiet, std::sync::atomic::Ordering::Relaxed);
    init_logging(&cli);
    let budget = match budget(&cli) {
        Ok(b) => b,
        Err(e) => {
            console::err(&format!("error: {e}\n"));
            return ExitCode::from(e.exit_code() as u8);
        }
    };
    let result = match cli.command {
        Command::Run { scenario, out, set, json } => run(&scenario, &out, &set, json, budget),
        Command::Sun(args) => sun(&args, budget),
        Command::Grid(args) => grid(&args, budget),
        Command::Terrain(cmd) => terrain(&cmd, budget),
        Command::Sweep(cmd) => sweep(cmd, budget),
        Command::Completions { shell } => {
            let mut script = Vec::new();
            clap_complete::generate(shell, &mut Cli::command(), "areo", &mut script);
            console::out(&String::from_utf8_lossy(&script))
        }
        Command::Rover(RoverCommand::Check { params, terrain, mu, moving, format, body }) => {
            use areo_scenario::rover_check::{Checked, check_file};
            check_file(&params, terrain, mu, moving, body.body()).and_then(|report| {
                let text = match (format, &report) {
                    (ReportFormat::Json, _) => print::json(&report)? + "\n",
                    (ReportFormat::Text, Checked::Physics(r)) => print::rover::text(r),
                    (ReportFormat::Text, Checked::Resources(r)) => print::rover::resources_text(r),
                };
                console::out(&text)
            })
        }
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            console::err(&format!("error: {e}\n"));
            ExitCode::from(e.exit_code() as u8)
        }
    }
}

fn sweep(cmd: SweepCommand, budget: Budget) -> Result<(), Error> {
    use areo_scenario::sweep;
    match cmd {
        SweepCommand::Expand { sweep: file, out, force } => {
            let tasks = sweep::expand_within(&file, &out, budget, force)?;
            console::out(&format!("{} tasks in {} (manifest.jsonl, tasks/)\n", tasks.len(), out.display()))?;
        }
        SweepCommand::Run { dir, index, force } => {
            let index = sweep::task_index(index)?;
            if let Some((n, capped)) = sweep::configure_threads() {
                if let Some(why) = capped {
                    tracing::warn!("{why}: using {n} threads");
                }
                tracing::info!("{n} threads (SLURM_CPUS_PER_TASK)");
            }
            match sweep::run_task(&dir, index, force, &progress_bar(), budget)? {
                sweep::TaskRun::Skipped(t) => {
                    console::out(&format!("task {index} ({}): finished before; skipped (--force runs it)\n", t.id))?
                }
                sweep::TaskRun::Ran(t, outcome) => {
                    console::out(&format!(
                        "task {index} ({}): {}\n",
                        t.id,
                        outcome.failure.as_ref().map_or_else(|| "done".to_string(), ToString::to_string)
                    ))?;
                }
            }
        }
        SweepCommand::Collect { dir, plot, against } => {
            let c = sweep::collect(&dir, plot.as_deref().zip(against.as_deref()))?;
            let mut text = format!("{} finished, {} missing, {} failed\n", c.finished, c.missing.len(), c.failed.len());
            for id in &c.missing {
                text += &format!("  missing {id}\n");
            }
            for (id, err) in &c.failed {
                text += &format!("  failed  {id}: {err}\n");
            }
            for f in &c.files {
                text += &format!("  wrote {}\n", f.display());
            }
            console::out(&text)?;
        }
        SweepCommand::Slurm { dir, parallel, cpus } => {
            let areo = std::env::current_exe()
                .map_err(|source| Error::Read { path: "(the running areo binary's path)".into(), source })?;
            console::out(&sweep::slurm_script(&dir, &areo, parallel.max(1), cpus.max(1))?)?;
        }
        SweepCommand::K8s { dir, image, claim, parallel } => {
            console::out(&sweep::k8s_job(&dir, &image, &claim, parallel.max(1))?)?;
        }
    }
    Ok(())
}

fn init_logging(cli: &Cli) {
    let level = match (cli.quiet, cli.verbose) {
        (true, _) => tracing::Level::ERROR,
        (false, 0) => tracing::Level::WARN,
        (false, 1) => tracing::Level::INFO,
        (false, 2) => tracing::Level::DEBUG,
        _ => tracing::Level::TRACE,
    };
    tracing_subscriber::fmt()
        .with_max_level(level)
        .with_writer(std::io::stderr)
        .with_ansi(std::io::stderr().is_terminal())
        .init();
}

/// An indicatif bar on stderr, drawn when stderr is a terminal (so `areo run … | tee
/// log` still shows it, and `2> file` or CI logs stay clean) and not `--quiet`.
struct Bar(ProgressBar);

impl Progress for Bar {
    fn start(&self, total: u64, message: &str) {
        self.0.reset();
        self.0.set_length(total);
        self.0.set_message(message.to_string());
    }
    fn advance(&self, n: u64) {
        self.0.inc(n);
    }
    fn set(&self, position: u64) {
        self.0.set_position(position);
    }
    fn rename(&self, message: &str) {
        self.0.set_message(message.to_string());
    }
    fn finish(&self) {
        self.0.finish_and_clear();
    }
}

fn progress_bar() -> Bar {
    let shown = std::io::stderr().is_terminal() && !QUIET.load(std::sync::atomic::Ordering::Relaxed);
    let target = if shown { ProgressDrawTarget::stderr() } else { ProgressDrawTarget::hidden() };
    let bar = ProgressBar::with_draw_target(None, target);
    if let Ok(style) = ProgressStyle::with_template("{msg:>12} [{bar:40}] {pos}/{len} ({eta})") {
        bar.set_style(style.progress_chars("=> "));
    }
    Bar(bar)
}

/// The limits from the flags, or this machine's defaults.
fn budget(cli: &Cli) -> Result<Budget, Error> {
    let mut b = Budget::for_this_machine();
    if let Some(gb) = cli.max_memory_gb {
        if !(gb > 0.0 && gb <= 1e6) {
            return Err(Error::usage(format!("--max-memory-gb {gb}"), "allowed 0 (exclusive)..=1000000"));
        }
        b.memory_bytes = (gb * f64::from(1u32 << 30)) as u64;
    }
    if let Some(steps) = cli.max_work {
        if !(1.0..=1e18).contains(&steps) {
            return Err(Error::usage(format!("--max-work {steps}"), "allowed 1..=1e18"));
        }
        b.work_steps = steps as u64;
    }
    Ok(b)
}

fn run(
    scenario: &std::path::Path,
    out: &std::path::Path,
    set: &[String],
    json: bool,
    budget: Budget,
) -> Result<(), Error> {
    let file = areo_scenario::format::load_with(scenario, set)?;
    tracing::info!(scenario = %file.path.display(), "loaded");
    let bar = progress_bar();
    let outcome = areo_scenario::run_into(&file, out, &bar, budget)?;
    if json {
        console::out(&(print::json(&print::run::RunJson::of(&file, &outcome))? + "\n"))?;
    } else {
        console::out(&print::run::text(&file, &outcome))?;
    }
    match outcome.failure {
        Some(failure) => Err(Error::Failed(failure)),
        None => Ok(()),
    }
}

/// A Sun given on the command line: elevation in −90..=90°, a finite azimuth.
fn check_sun(azimuth_deg: f64, elevation_deg: f64) -> Result<(), Error> {
    if !(-90.0..=90.0).contains(&elevation_deg) {
        return Err(Error::usage(format!("--sun-elevation {elevation_deg}"), "allowed -90..=90"));
    }
    if !azimuth_deg.is_finite() {
        return Err(Error::usage(format!("--sun-azimuth {azimuth_deg}"), "must be finite"));
    }
    Ok(())
}

/// The Sun direction of `areo terrain shadow`: as given, or that of `--utc` over the
/// map's middle (then also the line that says where it stands).
fn sun_for_shadow(
    file: &std::path::Path,
    azimuth: Option<f64>,
    elevation: Option<f64>,
    utc: Option<&str>,
    grid: impl FnOnce() -> Result<areo_scenario::terrain::Grid, Error>,
) -> Result<((f64, f64), String), Error> {
    match (utc, azimuth, elevation) {
        (Some(utc), _, _) => {
            let sun = areo_scenario::terrain::sun_over(file, &grid()?, utc)?;
            let said = print::terrain::sun_over(&sun);
            Ok(((sun.grid_azimuth_deg, sun.elevation_deg), said))
        }
        (None, Some(a), Some(e)) => Ok(((a, e), String::new())),
        // clap requires both or --utc.
        _ => Err(Error::usage("--sun-azimuth, --sun-elevation", "give both, or --utc")),
    }
}

fn terrain(cmd: &TerrainCommand, budget: Budget) -> Result<(), Error> {
    use areo_scenario::terrain as tt;
    // Each command checks its estimate once the DEM's size is known.
    let read = |file: &std::path::Path, command: DemCommand| -> Result<areo_scenario::terrain::Dem, Error> {
        let dem = tt::read_dem(file)?;
        budget.check(&command.estimate((dem.cols() * dem.rows()) as u64))?;
        Ok(dem)
    };
    let text = match cmd {
        TerrainCommand::Info { file, json } => {
            let info = tt::info(file, &read(file, DemCommand::Info)?);
            if *json { print::json(&info)? + "\n" } else { print::terrain::info(&info) }
        }
        TerrainCommand::Slope { file, out } => {
            tt::check_output(file, out)?;
            print::terrain::wrote(&tt::write_slope(&read(file, DemCommand::Slope)?, out)?)
        }
        TerrainCommand::Shadow { file, sun_azimuth, sun_elevation, utc, flat, method, tile: Some(tile), out } => {
            // A direction given by hand is checked before the DEM is touched.
            if let (Some(a), Some(e)) = (sun_azimuth, sun_elevation) {
                check_sun(*a, *e)?;
            }
            tt::check_output(file, out)?;
            let grid = || areo_scenario::terrain::geotiff_grid(file);
            let (sun, said) = sun_for_shadow(file, *sun_azimuth, *sun_elevation, utc.as_deref(), grid)?;
            let bar = progress_bar();
            let run = tt::write_shadow_tiled(file, sun, *flat, (*method).into(), *tile as usize, out, &budget, &bar)?;
            said + &print::terrain::tiled_shadow(&run)
        }
        TerrainCommand::Shadow { file, sun_azimuth, sun_elevation, utc, flat, method, tile: None, out } => {
            if let (Some(a), Some(e)) = (sun_azimuth, sun_elevation) {
                check_sun(*a, *e)?;
            }
            tt::check_output(file, out)?;
            let dem = read(file, DemCommand::Shadow)?;
            let grid = || Ok(areo_scenario::terrain::Grid::of(&dem));
            let ((azimuth, elevation), said) =
                sun_for_shadow(file, *sun_azimuth, *sun_elevation, utc.as_deref(), grid)?;
            let (files, lit) = tt::write_shadow(&dem, azimuth, elevation, *flat, (*method).into(), out)?;
            said + &print::terrain::fraction(lit, "in direct sun") + &print::terrain::wrote(&files)
        }
        TerrainCommand::Viewshed { file, from, out } => {
            tt::check_output(file, out)?;
            let (files, seen) = tt::write_viewshed(&read(file, DemCommand::Viewshed)?, from.0, from.1, from.2, out)
                .map_err(|e| match e {
                    // Name the DEM a value was refused for.
                    Error::Usage { what, message } => Error::usage(format!("{what} ({})", file.display()), message),
                    other => other,
                })?;
            print::terrain::fraction(seen, "visible") + &print::terrain::wrote(&files)
        }
        TerrainCommand::Horizon { file, sectors, tile: Some(tile), lowest_sun, out } => {
            tt::check_output(file, out)?;
            let run = tt::write_horizon_tiled(
                file,
                usize::from(*sectors),
                *lowest_sun,
                *tile as usize,
                out,
                &budget,
                &progress_bar(),
            )?;
            print::terrain::tiled_horizon(&run)
        }
        TerrainCommand::Horizon { file, sectors, tile: None, lowest_sun: _, out } => {
            let sectors = &usize::from(*sectors);
            tt::check_horizon_dir(file, out)?;
            print::terrain::wrote(&tt::write_horizon(
                &read(file, DemCommand::Horizon { sectors: *sectors })?,
                *sectors,
                out,
                &progress_bar(),
            )?)
        }
    };
    console::out(&text)
}

fn parse_xyz(s: &str) -> Result<(f64, f64, f64), String> {
    let v: Vec<f64> =
        s.split(',').map(|p| p.trim().parse::<f64>()).collect::<Result<_, _>>().map_err(|e| format!("{s:?}: {e}"))?;
    match v[..] {
        [x, y, h] if v.iter().all(|c| c.is_finite()) => Ok((x, y, h)),
        _ => Err(format!("{s:?}: expected X,Y,HEIGHT in metres")),
    }
}

fn grid(args: &GridArgs, budget: Budget) -> Result<(), Error> {
    let opts = areo_scenario::grid::GridOptions { replan: args.replan, seed: args.seed };
    let rows = areo_scenario::grid::solve_file(&args.map, &args.scen, opts, &progress_bar(), budget)?;
    console::out(&print::grid::rows(&rows, args.replan.is_some(), args.format)?)?;
    // Exit 3 when a goal was not reached, 1 when a length differs from the published one.
    let unreachable = rows.iter().filter(|r| r.found.is_infinite() && r.expected.is_finite()).count();
    let mismatched = rows.iter().filter(|r| r.mismatched).count();
    if unreachable > 0 {
        return Err(Error::Failed(Failure::NoPath { unreachable, scenarios: rows.len() }));
    }
    if mismatched > 0 {
        return Err(Error::Failed(Failure::Mismatched { mismatched, scenarios: rows.len() }));
    }
    Ok(())
}

fn sun(args: &SunArgs, budget: Budget) -> Result<(), Error> {
    use areo_scenario::sun::{Instants, SunRows, day_events, sol_events};
    let body_rows = |body, instants, site| areo_scenario::sun::body_rows_within(body, instants, site, budget);
    let site = args.lat.zip(args.lon);
    let body = args.body.body();
    if let Some(date) = &args.day {
        if args.body == BodyArg::Mars {
            return Err(Error::usage("--day", "is for the Moon and the Earth; on Mars give --sol"));
        }
        let (lat, lon) = site.ok_or_else(|| Error::usage("--day", "needs --lat and --lon"))?;
        return console::out(&print::sun::day(&day_events(body, date, lat, lon)?, args.format)?);
    }
    if let (Some(n), Some(landing)) = (args.mission_sol, &args.landing) {
        if args.body != BodyArg::Mars {
            return Err(Error::usage("--mission-sol", "counts Mars sols; on the Moon and the Earth give --day"));
        }
        let (lat, lon) = site.ok_or_else(|| Error::usage("--mission-sol", "needs --lat and --lon"))?;
        return console::out(&print::sun::sol(
            &areo_scenario::sun::mission_sol_events(landing, n, lat, lon)?,
            args.format,
        )?);
    }
    if let (Some(from), Some(to), Some(step)) = (&args.from, &args.to, &args.step) {
        return console::out(&print::sun::rows(
            &body_rows(body, Instants::Range { from, to, step }, site)?,
            args.format,
        )?);
    }
    let text = match (args.sol, &args.time, &args.times_file) {
        (Some(_), _, _) if args.body != BodyArg::Mars => {
            return Err(Error::usage(
                "--sol",
                format!(
                    "counts Mars sols; over the {body} give --time or --times-file (a file of instants, one per line)"
                ),
            ));
        }
        (Some(sol), _, _) => {
            let (lat, lon) = site.ok_or_else(|| Error::usage("--sol", "needs --lat and --lon"))?;
            print::sun::sol(&sol_events(sol, lat, lon)?, args.format)?
        }
        (None, Some(t), _) => print::sun::rows(&body_rows(body, Instants::One(t), site)?, args.format)?,
        (None, None, Some(path)) => print::sun::rows(&body_rows(body, Instants::File(path), site)?, args.format)?,
        (None, None, None) => print::sun::rows(&SunRows::Mars(Vec::new()), args.format)?,
    };
    console::out(&text)
}
