//! Checkpoint files: a DEM run's whole state, to resume it bit for bit (`dashpot dem
//! --restart FILE`).
//!
//! A file is a fixed header and a payload. The header (little-endian, [`HEADER_LEN`] bytes):
//! the magic bytes [`MAGIC`], the format's version ([`VERSION`]), the dimension, the scene's
//! hash ([`scene_hash`]: CRC-32 of dashpot's version, the scene and its laws' plugins), the
//! payload's length and its CRC-32. The payload is a [`Checkpoint`] in postcard's encoding
//! (serde): the scene's text, the laws' identity, the engine's state ([`EngineState`]) and
//! what the run's outputs need to go on.
//!
//! Reading checks everything before anything is used: the magic (not a checkpoint), the
//! version (another dashpot's format), the length (a truncated file, or bytes after the
//! payload), the checksum (a corrupted file), the decoding; the caller then checks the
//! scene's hash against the scene and laws it has (another scene, other plugins), and the
//! engine checks that the state fits it ([`crate::dem::Engine::restore_state`]). Writing goes
//! to a temporary file beside the target, flushed to disk, then renamed over it: a reader sees
//! the old checkpoint or the new one, never half of one.

use super::integrator::EngineState;
use serde::{Deserialize, Serialize};
use std::io::Write;
use std::path::{Path, PathBuf};

/// The first bytes of every checkpoint (a non-ASCII byte first, then a line ending and a
/// control byte: a file mangled as text, or a text file, does not start so).
pub const MAGIC: [u8; 8] = *b"\x89DPCK\r\n\x1a";

/// The format's version: a file of a later version is refused (its layout is not this one's).
/// Version 2 added the temperatures (an optional last field of the engine's state, itself the
/// payload's last field): a file of version 1 reads as one of version 2 without them (a run
/// without heat, as every run of version 1 was).
pub const VERSION: u32 = 2;

/// The oldest version read (see [`VERSION`]).
pub const OLDEST_VERSION: u32 = 1;

/// Bytes of the header: magic, version, dimension, scene hash, payload length, payload CRC-32.
pub const HEADER_LEN: usize = 8 + 4 + 4 + 4 + 8 + 4;

/// What a checkpoint holds besides its header.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct Checkpoint<const D: usize> {
    /// The scene's TOML text, as the run read it.
    pub scene: String,
    /// The laws' identity: each law's name, plugin and versions ([`scene_hash`] covers it).
    pub laws: String,
    /// The energy at the start of the run (J), which the final books report.
    pub energy_initial: f64,
    /// Trajectory frames written so far (`--out`), the first (the start) included.
    pub frames: u64,
    /// The engine's state.
    pub engine: EngineState<D>,
}

/// A checkpoint's header.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Header {
    /// The dimension of the run (2 or 3).
    pub dimension: u32,
    /// [`scene_hash`] of the run's scene and laws.
    pub scene_hash: u32,
}

/// Why a checkpoint cannot be written or read.
#[derive(Debug, thiserror::Error)]
pub enum CheckpointError {
    /// The file system refused.
    #[error("{}", path.display())]
    Io {
        /// The file.
        path: PathBuf,
        /// Why.
        source: std::io::Error,
    },
    /// The file is not a checkpoint, or not one this dashpot can read.
    #[error("{}: {what}; it cannot be resumed from", path.display())]
    Refused {
        /// The file.
        path: PathBuf,
        /// What is wrong with it.
        what: String,
    },
}

/// The hash a checkpoint's header keeps of its run: CRC-32 of dashpot's version, the
/// dimension, the scene (`scene`: canonical text, see [`canonical_scene`]) and the laws'
/// identity (`laws`).
pub fn scene_hash(dimension: u32, scene: &str, laws: &str) -> u32 {
    let mut h = crc32fast::Hasher::new();
    for part in [env!("CARGO_PKG_VERSION"), &dimension.to_string(), scene, laws] {
        h.update(&(part.len() as u64).to_le_bytes());
        h.update(part.as_bytes());
    }
    h.finalize()
}

/// The scene `text` in a canonical form (its TOML values, keys sorted, as JSON): the same for
/// two texts that differ only in comments, spacing or the order of keys.
pub fn canonical_scene(text: &str) -> Result<String, String> {
    let v: toml::Table = toml::from_str(text).map_err(|e| e.to_string())?;
    let v = serde_json::to_value(v).map_err(|e| e.to_string())?;
    // (serde_json's maps are sorted unless its preserve_order feature is on)
    Ok(v.to_string())
}

/// Writes `ck` to `path` under `header`, atomically (see the module doc).
pub fn write<const D: usize>(path: &Path, header: Header, ck: &Checkpoint<D>) -> Result<(), CheckpointError> {
    let io = |source| CheckpointError::Io {
        path: path.to_path_buf(),
        source,
    };
    let payload = postcard::to_stdvec(ck).map_err(|e| io(std::io::Error::other(e)))?;
    let mut bytes = Vec::with_capacity(HEADER_LEN + payload.len());
    bytes.extend_from_slice(&MAGIC);
    bytes.extend_from_slice(&VERSION.to_le_bytes());
    bytes.extend_from_slice(&header.dimension.to_le_bytes());
    bytes.extend_from_slice(&header.scene_hash.to_le_bytes());
    bytes.extend_from_slice(&(payload.len() as u64).to_le_bytes());
    bytes.extend_from_slice(&crc32fast::hash(&payload).to_le_bytes());
    bytes.extend_from_slice(&payload);
    let dir = path
        .parent()
        .filter(|d| !d.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    std::fs::create_dir_all(dir).map_err(io)?;
    let mut tmp = tempfile::Builder::new()
        .prefix(".checkpoint-")
        .tempfile_in(dir)
        .map_err(io)?;
    tmp.write_all(&bytes).map_err(io)?;
    tmp.as_file().sync_all().map_err(io)?;
    tmp.persist(path).map_err(|e| io(e.error))?;
    Ok(())
}

/// Reads the header of the checkpoint `path` and checks its payload (length and checksum):
/// the header and the payload's bytes, or why the file is refused.
pub fn read_raw(path: &Path) -> Result<(Header, Vec<u8>), CheckpointError> {
    let refuse = |what: String| CheckpointError::Refused {
        path: path.to_path_buf(),
        what,
    };
    let bytes = std::fs::read(path).map_err(|source| CheckpointError::Io {
        path: path.to_path_buf(),
        source,
    })?;
    if bytes.len() < MAGIC.len() || bytes[..MAGIC.len()] != MAGIC {
        return Err(refuse(
            "not a dashpot checkpoint (its first bytes are not dashpot's)".into(),
        ));
    }
    if bytes.len() < HEADER_LEN {
        return Err(refuse(format!(
            "truncated: {} bytes, shorter than the {HEADER_LEN}-byte header",
            bytes.len()
        )));
    }
    let u32_at = |k: usize| u32::from_le_bytes(bytes[k..k + 4].try_into().expect("4 bytes"));
    let version = u32_at(8);
    if !(OLDEST_VERSION..=VERSION).contains(&version) {
        return Err(refuse(format!(
            "written in checkpoint format version {version}; this dashpot ({}) reads versions {OLDEST_VERSION} to {VERSION}",
            env!("CARGO_PKG_VERSION")
        )));
    }
    let header = Header {
        dimension: u32_at(12),
        scene_hash: u32_at(16),
    };
    let len = u64::from_le_bytes(bytes[20..28].try_into().expect("8 bytes"));
    let crc = u32_at(28);
    let have = (bytes.len() - HEADER_LEN) as u64;
    if have < len {
        return Err(refuse(format!(
            "truncated: the header announces {len} bytes of state, the file holds {have}"
        )));
    }
    if have > len {
        return Err(refuse(format!(
            "{} bytes follow the {len} bytes of state the header announces",
            have - len
        )));
    }
    let mut payload = bytes[HEADER_LEN..].to_vec();
    if crc32fast::hash(&payload) != crc {
        return Err(refuse(
            "corrupted: its checksum does not match its contents".into(),
        ));
    }
    if version == 1 {
        // version 2's last field, the temperatures, absent: postcard's `None`
        payload.push(0);
    }
    if !(header.dimension == 2 || header.dimension == 3) {
        return Err(refuse(format!(
            "its dimension {} is not 2 or 3",
            header.dimension
        )));
    }
    Ok((header, payload))
}

/// Decodes the payload read by [`read_raw`] from `path`, of a run in `D` dimensions.
pub fn decode<const D: usize>(path: &Path, payload: &[u8]) -> Result<Checkpoint<D>, CheckpointError> {
    let (ck, rest) =
        postcard::take_from_bytes::<Checkpoint<D>>(payload).map_err(|e| CheckpointError::Refused {
            path: path.to_path_buf(),
            what: format!("its state cannot be decoded ({e})"),
        })?;
    if !rest.is_empty() {
        return Err(CheckpointError::Refused {
            path: path.to_path_buf(),
            what: format!("{} bytes follow its state", rest.len()),
        });
    }
    Ok(ck)
}
