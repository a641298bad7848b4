//! `dashpot dem`'s checkpoints: when to write them (every N steps or every so many seconds of
//! wall-clock time, and on Ctrl-C or SIGTERM), where, and how a run resumes from one
//! (`--restart FILE`). The file format is [`crate::dem::checkpoint`]'s.

use crate::dem::checkpoint::{self, Checkpoint, Header};
use crate::dem::scene::{PairPlan, SceneFile};
use crate::dem::Engine;
use crate::registry::Registry;
use anyhow::{Context, Result};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};

/// How often `--checkpoint-every` writes a checkpoint.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Every {
    /// Every this many steps.
    Steps(u64),
    /// Every this much wall-clock time.
    Wall(Duration),
}

impl std::str::FromStr for Every {
    type Err = String;

    /// `5000` (steps), or a wall-clock time: `90s`, `10min`, `2h`.
    fn from_str(s: &str) -> Result<Every, String> {
        let bad = || {
            format!(
                "'{s}' is not a checkpoint interval: give a number of steps (e.g. 5000, >= 1) or a wall-clock time (e.g. 90s, 10min, 2h, > 0)"
            )
        };
        let s = s.trim();
        if let Ok(n) = s.parse::<u64>() {
            return if n >= 1 { Ok(Every::Steps(n)) } else { Err(bad()) };
        }
        let split = s.find(|c: char| c.is_ascii_alphabetic()).ok_or_else(bad)?;
        let (num, unit) = s.split_at(split);
        let x: f64 = num.trim().parse().map_err(|_| bad())?;
        let scale = match unit {
            "s" => 1.0,
            "min" | "m" => 60.0,
            "h" => 3600.0,
            _ => return Err(bad()),
        };
        let secs = x * scale;
        if !(secs.is_finite() && secs > 0.0) {
            return Err(bad());
        }
        Ok(Every::Wall(Duration::from_secs_f64(secs)))
    }
}

/// The run stopped on Ctrl-C or SIGTERM after writing a checkpoint (the CLI exits with 130).
#[derive(Debug)]
pub struct Interrupted(pub String);

impl std::fmt::Display for Interrupted {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for Interrupted {}

/// Steps per block of the run at most while a signal may ask for a checkpoint: the run looks
/// at the signal between blocks (the state is the same bit for bit whatever the blocks).
pub const BLOCK: u64 = 200;

/// A run's checkpoints: where, how often, and the signal flag.
pub struct Checkpoints {
    /// The file written.
    pub path: PathBuf,
    every: Option<Every>,
    last_step: u64,
    last_time: Instant,
    stop: Arc<AtomicBool>,
    /// The scene's text and the laws' identity the checkpoints carry.
    scene: String,
    laws: String,
    /// The header's scene hash.
    hash: u32,
    /// The energy at the start of the run (J).
    pub energy_initial: f64,
    /// Checkpoints written.
    pub written: u64,
}

impl Checkpoints {
    /// The checkpoints of a run of `scene` (its text) under the laws of `plan` from `reg`,
    /// written to `path` every `every` (and on a signal); Ctrl-C and SIGTERM are caught from
    /// here on.
    pub fn new(
        reg: &Registry,
        plan: &PairPlan,
        dimension: u32,
        scene: &str,
        path: PathBuf,
        every: Option<Every>,
    ) -> Result<Checkpoints> {
        let laws = laws_identity(reg, plan)?;
        let canon = checkpoint::canonical_scene(scene).map_err(anyhow::Error::msg)?;
        let stop = Arc::new(AtomicBool::new(false));
        for sig in [signal_hook::consts::SIGINT, signal_hook::consts::SIGTERM] {
            // a second signal while the first is being served ends the process at once
            signal_hook::flag::register_conditional_shutdown(sig, 130, Arc::clone(&stop))
                .context("installing the Ctrl-C handler")?;
            signal_hook::flag::register(sig, Arc::clone(&stop)).context("installing the Ctrl-C handler")?;
        }
        Ok(Checkpoints {
            hash: checkpoint::scene_hash(dimension, &canon, &laws),
            path,
            every,
            last_step: 0,
            last_time: Instant::now(),
            stop,
            scene: scene.to_string(),
            laws,
            energy_initial: 0.0,
            written: 0,
        })
    }

    /// The run starts (or resumes) at step `step`, with the energy `energy_initial` (J) at its
    /// start.
    pub fn start(&mut self, energy_initial: f64, step: u64) {
        self.energy_initial = energy_initial;
        self.last_step = step;
        self.last_time = Instant::now();
    }

    /// The step count at which the block starting at step `s` should end at the latest.
    pub fn next_stop(&self, s: u64) -> u64 {
        match self.every {
            Some(Every::Steps(n)) => (self.last_step + n).max(s + 1).min(s + BLOCK),
            _ => s + BLOCK,
        }
    }

    /// Whether a signal asked the run to stop.
    pub fn interrupted(&self) -> bool {
        self.stop.load(Ordering::Relaxed)
    }

    /// Whether a checkpoint is due after step `steps`.
    pub fn due(&self, steps: u64) -> bool {
        match self.every {
            Some(Every::Steps(n)) => steps >= self.last_step + n,
            Some(Every::Wall(d)) => self.last_time.elapsed() >= d,
            None => false,
        }
    }

    /// Writes the checkpoint of `e` now, `frames` trajectory frames having been written.
    pub fn write<const D: usize>(&mut self, e: &Engine<D>, frames: u64) -> Result<()> {
        let ck = Checkpoint {
            scene: self.scene.clone(),
            laws: self.laws.clone(),
            energy_initial: self.energy_initial,
            frames,
            engine: e.save_state(),
        };
        let header = Header {
            dimension: D as u32,
            scene_hash: self.hash,
        };
        checkpoint::write(&self.path, header, &ck).context("writing the checkpoint")?;
        self.last_step = e.steps();
        self.last_time = Instant::now();
        self.written += 1;
        Ok(())
    }

    /// The scene's hash the checkpoints carry.
    pub fn hash(&self) -> u32 {
        self.hash
    }
}

/// The laws' identity a checkpoint carries: each law's name, plugin crate and versions
/// (another plugin build of the same version is taken as the same law).
pub fn laws_identity(reg: &Registry, plan: &PairPlan) -> Result<String> {
    let mut out = String::new();
    for t in plan.tables() {
        let p = crate::output::Provenance::of(reg, &t.name, &t.param_values())?;
        out.push_str(&format!(
            "{} {} {} {} sdk {};",
            p.kind, p.law, p.plugin_name, p.plugin_version, p.plugin_sdk
        ));
    }
    Ok(out)
}

/// Where checkpoints go unless `--checkpoint` says: the file restarted from, else
/// `DIR/checkpoint.dpck` with `--out DIR`, else the scene's name with the extension `.dpck` in
/// the current directory (not beside the scene: an example's folder is not the user's).
pub fn default_path(restart: Option<&Path>, out: Option<&Path>, scene: Option<&Path>) -> PathBuf {
    if let Some(r) = restart {
        return r.to_path_buf();
    }
    if let Some(d) = out {
        return d.join("checkpoint.dpck");
    }
    let stem = scene.and_then(Path::file_stem).unwrap_or("dem".as_ref());
    PathBuf::from(stem).with_extension("dpck")
}

/// A checkpoint read for `--restart`: its header and its payload (checked), to decode in the
/// run's dimension.
pub struct Resume {
    /// The file.
    pub path: PathBuf,
    /// Its header.
    pub header: Header,
    /// Its payload.
    pub payload: Vec<u8>,
}

impl Resume {
    /// Reads `path` (every check of [`checkpoint::read_raw`]).
    pub fn read(path: &Path) -> Result<Resume> {
        let (header, payload) = checkpoint::read_raw(path)?;
        Ok(Resume {
            path: path.to_path_buf(),
            header,
            payload,
        })
    }

    /// The checkpoint, of a run in `D` dimensions; with `scene` (`--scene` given too: its
    /// text and path), refused unless it is the checkpoint's scene.
    pub fn decode<const D: usize>(&self, scene: Option<(&str, &Path)>) -> Result<Checkpoint<D>> {
        let ck = checkpoint::decode::<D>(&self.path, &self.payload)?;
        if let Some((text, path)) = scene {
            let same = checkpoint::canonical_scene(text).ok() == checkpoint::canonical_scene(&ck.scene).ok();
            if !same {
                anyhow::bail!(
                    "{} was written by a run of another scene than {}: restart it alone (--restart {} without --scene runs the scene it holds), or from a checkpoint of this scene",
                    self.path.display(),
                    path.display(),
                    self.path.display()
                );
            }
        }
        Ok(ck)
    }

    /// Puts `ck` (decoded by [`Resume::decode`]) into `e`, made from the checkpoint's scene,
    /// after checking the header's scene hash against `hash`, the one of this scene and these
    /// laws ([`Checkpoints::hash`]).
    pub fn restore<const D: usize>(&self, ck: Checkpoint<D>, hash: u32, e: &mut Engine<D>) -> Result<()> {
        if self.header.scene_hash != hash {
            anyhow::bail!(
                "{}: its scene hash {:08x} is not {hash:08x}, that of its scene with the laws' plugins found now (another dashpot version or other plugins: the run would not go on as it started); it cannot be resumed from",
                self.path.display(),
                self.header.scene_hash
            );
        }
        e.restore_state(ck.engine)
            .with_context(|| format!("restoring {}", self.path.display()))
    }
}

/// Whether `text` (a trajectory of `n` particles per frame) holds exactly `frames` frames.
pub fn trajectory_frames(text: &str, n: usize) -> u64 {
    let lines = text.lines().count();
    if lines % (n + 2) == 0 {
        (lines / (n + 2)) as u64
    } else {
        u64::MAX
    }
}

/// Parses the scene `text` from `path`.
pub fn parse_scene(text: &str, path: &Path) -> Result<SceneFile> {
    SceneFile::parse(text).with_context(|| format!("in {}", path.display()))
}
