//! A d3d9.dll of the user's choosing under Wine (`conform --d3d9 PATH`, docs/CONFORMANCE.md,
//! "Another d3d9.dll: DXVK"): the DLL is copied beside a copy of the replayer in the run's own
//! folder, Wine is told to load it (`WINEDLLOVERRIDES` with `d3d9=n`), and the device is named
//! honestly: the DLL's file name and version (its version resource, and DXVK's embedded
//! version string), the Vulkan device DXVK reports in its log, and an adapter description set
//! through `DXVK_CONFIG` so that DXVK does not present lavapipe as another vendor's GPU.

use std::fs;
use std::path::{Path, PathBuf};

/// Lavapipe's Vulkan ICD on Debian: pinned with `VK_ICD_FILENAMES` unless the user set it, since
/// DXVK skips CPU adapters when a GPU is present.
pub const LAVAPIPE_ICD: &str = "/usr/share/vulkan/icd.d/lvp_icd.x86_64.json";

/// The d3d9.dll a run loads, with what could be read of its identity.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct D3d9Dll {
    /// The DLL as the user named it.
    pub path: PathBuf,
    /// Its identity: file name, product and versions found in it.
    pub name: String,
    /// Whether it is a DXVK build (its version resource's ProductName, or DXVK's strings).
    pub dxvk: bool,
}

/// Checks `path` names an existing regular file (links followed): one line when not.
pub fn check(path: &Path) -> Result<(), String> {
    match fs::metadata(path) {
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => {
            Err(format!("--d3d9 {}: no such file", path.display()))
        }
        Err(e) => Err(format!("--d3d9 {}: {e}", path.display())),
        Ok(m) if !m.is_file() => Err(format!(
            "--d3d9 {}: not a regular file (give the path of a d3d9.dll)",
            path.display()
        )),
        Ok(_) => Ok(()),
    }
}

impl D3d9Dll {
    /// Reads the DLL at `path` and names it from its bytes.
    pub fn read(path: &Path) -> Result<(D3d9Dll, Vec<u8>), String> {
        check(path)?;
        let bytes = fs::read(path).map_err(|e| format!("--d3d9 {}: {e}", path.display()))?;
        if !bytes.starts_with(b"MZ") {
            return Err(format!(
                "--d3d9 {}: not a Windows DLL (no MZ header)",
                path.display()
            ));
        }
        let file = path
            .file_name()
            .map(|f| f.to_string_lossy().into_owned())
            .unwrap_or_default();
        let (name, dxvk) = describe(&file, &bytes);
        let dll = D3d9Dll {
            path: path.to_path_buf(),
            name,
            dxvk,
        };
        Ok((dll, bytes))
    }

    /// The adapter description DXVK is given (`d3d9.customDeviceDesc`): the DLL's name and
    /// the Vulkan driver it runs on, instead of DXVK's default of a real GPU's name.
    pub fn device_desc(&self, icd_pinned: bool) -> String {
        let under = if icd_pinned {
            "lavapipe"
        } else {
            "the Vulkan ICD of VK_ICD_FILENAMES"
        };
        format!("{} on {under}", self.name)
    }

    /// The environment of the replayer: `(name, value, forced)`; a variable not forced is set
    /// only where the caller's environment does not set it. `WINEDLLOVERRIDES` always ends with
    /// `d3d9=n` (the user's overrides kept before it).
    pub fn environment(&self, user_overrides: Option<&str>) -> Vec<(String, String, bool)> {
        let icd_pinned = std::env::var_os("VK_ICD_FILENAMES").is_none();
        let overrides = match user_overrides {
            Some(u) if !u.is_empty() => format!("{u};d3d9=n"),
            _ => "mscoree,mshtml=;d3d9=n".to_string(),
        };
        let desc = self.device_desc(icd_pinned).replace('"', "'");
        vec![
            ("WINEDLLOVERRIDES".into(), overrides, true),
            ("VK_ICD_FILENAMES".into(), LAVAPIPE_ICD.into(), false),
            (
                "DXVK_CONFIG".into(),
                format!("d3d9.customDeviceDesc = \"{desc}\""),
                false,
            ),
            // DXVK's log goes to the replayer's output (REPORT/replayer.log), not beside the exe.
            ("DXVK_LOG_PATH".into(), "none".into(), false),
            ("DXVK_LOG_LEVEL".into(), "info".into(), false),
        ]
    }
}

/// Names a DLL from its bytes: `FILE (PRODUCT VERSION, file version X)`, from the version
/// resource's `ProductName` and `FileVersion` strings and, for DXVK, its embedded `vX.Y.Z`
/// version string (DXVK's version resource carries Windows' own file version, not DXVK's).
pub fn describe(file: &str, bytes: &[u8]) -> (String, bool) {
    let product = resource_string(bytes, "ProductName");
    let file_version = resource_string(bytes, "FileVersion");
    let dxvk = product.as_deref() == Some("DXVK") || find(bytes, b"DXVK: ").is_some();
    let mut parts = Vec::new();
    if dxvk {
        let version = dxvk_version(bytes);
        parts.push(match version {
            Some(v) => format!("DXVK {v}"),
            None => "DXVK".to_string(),
        });
    } else if let Some(p) = &product {
        parts.push(p.clone());
    }
    if let Some(v) = file_version {
        parts.push(format!("file version {v}"));
    }
    let name = if parts.is_empty() {
        file.to_string()
    } else {
        format!("{file} ({})", parts.join(", "))
    };
    (name, dxvk)
}

fn find(hay: &[u8], needle: &[u8]) -> Option<usize> {
    hay.windows(needle.len()).position(|w| w == needle)
}

/// A `VS_VERSIONINFO` string value: the UTF-16LE key, its NUL, padding, then the value.
fn resource_string(bytes: &[u8], key: &str) -> Option<String> {
    let mut pattern: Vec<u8> = key.encode_utf16().flat_map(u16::to_le_bytes).collect();
    pattern.extend([0, 0]);
    let at = find(bytes, &pattern)? + pattern.len();
    let units: Vec<u16> = bytes[at..]
        .chunks_exact(2)
        .map(|c| u16::from_le_bytes([c[0], c[1]]))
        .skip_while(|&u| u == 0)
        .take_while(|&u| u != 0)
        .take(256)
        .collect();
    let s = String::from_utf16(&units).ok()?;
    (!s.is_empty()).then_some(s)
}

/// DXVK's version string (`DXVK_VERSION`, such as `v2.6.2`, `v2.6.2+` from a tag's checkout, or `v2.6.2-12-gabcdef`): the first
/// NUL-terminated ASCII string of the form `vN.N...` in the DLL.
fn dxvk_version(bytes: &[u8]) -> Option<String> {
    bytes
        .split(|&b| b == 0)
        .filter_map(|s| std::str::from_utf8(s).ok())
        .find(|s| {
            let Some(rest) = s.strip_prefix('v') else {
                return false;
            };
            let mut dots = rest.split(['-', '+']).next().unwrap_or("").split('.');
            let numeric = |p: &str| !p.is_empty() && p.bytes().all(|b| b.is_ascii_digit());
            s.len() <= 40
                && dots.next().is_some_and(numeric)
                && dots.next().is_some_and(numeric)
                && dots.all(numeric)
                && rest
                    .bytes()
                    .all(|b| b.is_ascii_alphanumeric() || b".-+".contains(&b))
        })
        .map(str::to_string)
}

/// What DXVK's log (the replayer's output) says of the Vulkan device it chose: the line
/// `info:  NAME:` followed by `info:    Driver : DRIVER VERSION` (DXVK's
/// `DxvkAdapter::logAdapterInfo`), as `NAME (DRIVER VERSION)`. `None` when the log has none
/// (not DXVK, or no device created).
pub fn vulkan_device_from_log(log: &str) -> Option<String> {
    let lines: Vec<&str> = log.lines().collect();
    lines.windows(2).rev().find_map(|w| {
        let name = w[0].trim_start_matches("info:").trim();
        let driver = w[1].trim_start_matches("info:").trim();
        let driver = driver.strip_prefix("Driver :")?.trim();
        let name = name.strip_suffix(':')?;
        Some(format!("{name} (driver {driver})"))
    })
}

/// The DXVK version the log reports (`info:  DXVK: v2.6.2`).
pub fn dxvk_version_from_log(log: &str) -> Option<String> {
    log.lines().find_map(|l| {
        l.split_once("DXVK: v")
            .map(|(_, v)| format!("v{}", v.trim()))
    })
}

/// Copies `bytes` (the replayer, the DLL) to `folder/name` when that file is not already the
/// same bytes; `folder` is the run's own (`REPORT/d3d9`), created when missing.
pub fn place(
    folder: &Path,
    name: &str,
    bytes: &[u8],
    inputs: &[PathBuf],
) -> Result<PathBuf, String> {
    fs::create_dir_all(folder).map_err(|e| format!("cannot create {}: {e}", folder.display()))?;
    let path = folder.join(name);
    if fs::read(&path).is_ok_and(|b| b == bytes) {
        return Ok(path);
    }
    pointillist_image::output::Destination::check(&path, inputs)
        .and_then(|d| d.write_bytes(bytes))
        .map_err(|e| e.to_string())?;
    Ok(path)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn utf16(s: &str) -> Vec<u8> {
        s.encode_utf16().flat_map(u16::to_le_bytes).collect()
    }

    #[test]
    fn names_a_dxvk_dll_from_its_resource_and_version_string() {
        let mut dll = b"MZ\x90\0junk\0v2.6.2\0DXVK: \0".to_vec();
        dll.extend(utf16("ProductName"));
        dll.extend([0, 0, 0, 0]);
        dll.extend(utf16("DXVK"));
        dll.extend([0, 0]);
        dll.extend(utf16("FileVersion"));
        dll.extend([0, 0]);
        dll.extend(utf16("10.0.17763.1"));
        dll.extend([0, 0]);
        let (name, dxvk) = describe("d3d9.dll", &dll);
        assert!(dxvk);
        assert_eq!(name, "d3d9.dll (DXVK v2.6.2, file version 10.0.17763.1)");
    }

    #[test]
    fn a_tag_checkouts_version_string_keeps_its_plus() {
        // What a build of DXVK's v2.6.2 tag holds: "DXVK: \0v2.6.2+\0Build: \0x86_64\0".
        let dll = b"MZ\x90\0e.Game: \0DXVK: \0v2.6.2+\0Build: \0x86_64\0 \0gcc\0".to_vec();
        assert_eq!(dxvk_version(&dll).as_deref(), Some("v2.6.2+"));
        assert_eq!(
            dxvk_version(b"MZ\0v2.6.2-12-gabcdef\0").as_deref(),
            Some("v2.6.2-12-gabcdef")
        );
        assert_eq!(dxvk_version(b"MZ\0v2.x\0v\0").as_deref(), None);
    }

    #[test]
    fn a_dll_without_version_information_is_named_by_its_file() {
        assert_eq!(
            describe("d3d9.dll", b"MZ\0\0plain"),
            ("d3d9.dll".to_string(), false)
        );
    }

    #[test]
    fn reads_the_vulkan_device_and_version_from_dxvk_log() {
        let log = "info:  Game: replayer.exe\ninfo:  DXVK: v2.6.2\n\
                   info:  llvmpipe (LLVM 15.0.6, 256 bits):\n\
                   info:    Driver : llvmpipe 0.0.1\ninfo:    Memory Heap[0]: \n";
        assert_eq!(
            vulkan_device_from_log(log).as_deref(),
            Some("llvmpipe (LLVM 15.0.6, 256 bits) (driver llvmpipe 0.0.1)")
        );
        assert_eq!(dxvk_version_from_log(log).as_deref(), Some("v2.6.2"));
        assert_eq!(vulkan_device_from_log("wine: nothing\n"), None);
    }

    #[test]
    fn overrides_keep_the_users_and_load_the_native_d3d9() {
        let dll = D3d9Dll {
            path: "d3d9.dll".into(),
            name: "d3d9.dll (DXVK v2.6.2)".into(),
            dxvk: true,
        };
        let env = dll.environment(Some("dxgi=n"));
        assert_eq!(
            env[0],
            ("WINEDLLOVERRIDES".into(), "dxgi=n;d3d9=n".into(), true)
        );
        let env = dll.environment(None);
        assert_eq!(env[0].1, "mscoree,mshtml=;d3d9=n");
        assert!(env.iter().any(|(k, v, forced)| k == "DXVK_CONFIG"
            && v.contains("customDeviceDesc = \"d3d9.dll (DXVK v2.6.2) on")
            && !forced));
    }
}
