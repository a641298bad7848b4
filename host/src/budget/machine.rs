//! What the machine has: the memory this process may still take (`/proc/meminfo`, cgroup v1
//! and v2 limits, `DASHPOT_MEMORY_AVAILABLE`) and this process's resident memory
//! (`/proc/self/status`).

use std::path::{Path, PathBuf};

/// The memory this process may still take.
#[derive(Debug, Clone, PartialEq)]
pub struct Memory {
    /// Bytes.
    pub available: u64,
    /// Where the figure comes from, e.g. "MemAvailable in /proc/meminfo".
    pub source: String,
}

impl Memory {
    /// The memory available now: `DASHPOT_MEMORY_AVAILABLE` if set, else the least of
    /// `MemAvailable` (`/proc/meminfo`) and the room left under each cgroup memory limit of this
    /// process (v2 `memory.max`, v1 `memory.limit_in_bytes`, less what the group uses beyond its
    /// reclaimable page cache). Where none can be read (not Linux), unbounded.
    pub fn now() -> Memory {
        if let Ok(s) = std::env::var("DASHPOT_MEMORY_AVAILABLE") {
            if let Some(b) = super::parse_bytes(&s) {
                return Memory {
                    available: b,
                    source: format!("DASHPOT_MEMORY_AVAILABLE = {s}"),
                };
            }
        }
        let mut best = Memory {
            available: u64::MAX,
            source: "no limit found".into(),
        };
        if let Some(b) = meminfo_available() {
            best = Memory {
                available: b,
                source: "MemAvailable in /proc/meminfo".into(),
            };
        }
        for (room, dir) in cgroup_rooms() {
            if room < best.available {
                best = Memory {
                    available: room,
                    source: format!("the memory limit of the cgroup {}", dir.display()),
                };
            }
        }
        best
    }
}

/// `MemAvailable` of `/proc/meminfo` (bytes).
fn meminfo_available() -> Option<u64> {
    let text = std::fs::read_to_string("/proc/meminfo").ok()?;
    kb_field(&text, "MemAvailable:")
}

/// A `NAME:   123 kB` line's value in bytes.
fn kb_field(text: &str, name: &str) -> Option<u64> {
    let line = text.lines().find(|l| l.starts_with(name))?;
    let kb: u64 = line[name.len()..].split_whitespace().next()?.parse().ok()?;
    Some(kb.saturating_mul(1024))
}

/// A file holding one number (or `max`: none).
fn number(p: &Path) -> Option<u64> {
    let t = std::fs::read_to_string(p).ok()?;
    t.trim().parse().ok()
}

/// A `name value` line of a `memory.stat` file.
fn stat_field(dir: &Path, name: &str) -> Option<u64> {
    let t = std::fs::read_to_string(dir.join("memory.stat")).ok()?;
    t.lines().find_map(|l| {
        let mut it = l.split_whitespace();
        (it.next()? == name).then(|| it.next()?.parse().ok())?
    })
}

/// The room left under each memory limit of this process's cgroups and their ancestors
/// (bytes), with the group's directory.
fn cgroup_rooms() -> Vec<(u64, PathBuf)> {
    let Ok(text) = std::fs::read_to_string("/proc/self/cgroup") else {
        return Vec::new();
    };
    let mut out = Vec::new();
    for line in text.lines() {
        let mut f = line.splitn(3, ':');
        let (Some(_), Some(ctrl), Some(path)) = (f.next(), f.next(), f.next()) else {
            continue;
        };
        let path = path.trim_start_matches('/');
        // (v2: the unified hierarchy, "0::/path"; v1: the memory controller's)
        let roots: &[&str] = if ctrl.is_empty() {
            &["/sys/fs/cgroup", "/sys/fs/cgroup/unified"]
        } else if ctrl.split(',').any(|c| c == "memory") {
            &["/sys/fs/cgroup/memory"]
        } else {
            continue;
        };
        for root in roots {
            let root = Path::new(root);
            // inside a container the group's path may not exist under the mount: its root is
            // then the group itself
            let mut dir = root.join(path);
            if !dir.is_dir() {
                dir = root.to_path_buf();
            }
            loop {
                if let Some(room) = room_in(&dir, ctrl.is_empty()) {
                    out.push((room, dir.clone()));
                }
                if dir == root {
                    break;
                }
                match dir.parent() {
                    Some(p) if p.starts_with(root) => dir = p.to_path_buf(),
                    _ => break,
                }
            }
        }
    }
    out
}

/// The room under one group's limit (bytes), if it has one: the limit less the group's usage
/// beyond its inactive page cache (which the kernel reclaims before refusing memory).
fn room_in(dir: &Path, v2: bool) -> Option<u64> {
    let (limit, usage, cache) = if v2 {
        (
            number(&dir.join("memory.max"))?,
            number(&dir.join("memory.current")).unwrap_or(0),
            stat_field(dir, "inactive_file").unwrap_or(0),
        )
    } else {
        (
            number(&dir.join("memory.limit_in_bytes"))?,
            number(&dir.join("memory.usage_in_bytes")).unwrap_or(0),
            stat_field(dir, "total_inactive_file").unwrap_or(0),
        )
    };
    // (v1 reports "no limit" as a page-rounded 2^63)
    if limit >= 1 << 60 {
        return None;
    }
    Some(limit.saturating_sub(usage.saturating_sub(cache)))
}

/// This process's resident memory (bytes).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Rss {
    /// Resident now (`VmRSS`).
    pub now: u64,
    /// The peak so far (`VmHWM`).
    pub peak: u64,
}

/// This process's resident memory (zeros where `/proc/self/status` cannot be read).
pub fn rss() -> Rss {
    let text = std::fs::read_to_string("/proc/self/status").unwrap_or_default();
    Rss {
        now: kb_field(&text, "VmRSS:").unwrap_or(0),
        peak: kb_field(&text, "VmHWM:").unwrap_or(0),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_machine_reports_some_memory_and_this_process_some_rss() {
        let m = Memory::now();
        assert!(m.available > 0, "{m:?}");
        if cfg!(target_os = "linux") {
            let r = rss();
            assert!(r.now > 1 << 20 && r.peak >= r.now, "{r:?}");
        }
    }

    #[test]
    fn meminfo_lines_read_in_bytes() {
        let t = "MemTotal:       24683656 kB\nMemAvailable:   22690568 kB\n";
        assert_eq!(kb_field(t, "MemAvailable:"), Some(22690568 * 1024));
        assert_eq!(kb_field(t, "Nope:"), None);
    }
}
