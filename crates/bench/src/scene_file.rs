//! The workloads as scene files (docs/spec/SCENE.md), so that `pointillist render` can draw them
//! as a user runs it: the vertices in a raw `file =` buffer beside the TOML, textures inline.

use std::fmt::Write as _;
use std::io;
use std::path::{Path, PathBuf};

use pointillist_core::texture::Texture;

use crate::workloads::{Kind, Workload};

impl Workload {
    /// Writes this workload as `DIR/<name>.toml` and its vertex buffer as `DIR/<name>.bin`;
    /// returns the scene's path. `pointillist render` of it draws what one frame of the
    /// workload draws.
    pub fn write_scene(&self, dir: &Path) -> io::Result<PathBuf> {
        let name = self.kind.name();
        let bin = format!("{name}.bin");
        std::fs::write(dir.join(&bin), &self.vertices)?;
        let mut toml = self.scene_head();
        let fvf = match self.kind {
            Kind::W1 | Kind::W3 => "XYZRHW | DIFFUSE",
            Kind::W2 => "XYZRHW | PSIZE | DIFFUSE",
            Kind::W4 => "XYZ | PSIZE | DIFFUSE",
        };
        let _ = write!(toml, "\n[[draw]]\nfvf = \"{fvf}\"\nfile = \"{bin}\"\n");
        let path = dir.join(format!("{name}.toml"));
        std::fs::write(&path, toml)?;
        Ok(path)
    }

    /// Writes `DIR/empty.toml`: this workload's target with no draw, the cost of a render that
    /// draws nothing (process start, clear, PNG of the cleared target).
    pub fn write_empty_scene(&self, dir: &Path) -> io::Result<PathBuf> {
        let path = dir.join(format!("{}_empty.toml", self.kind.name()));
        std::fs::write(
            &path,
            format!(
                "format = 1\n[target]\nwidth = {}\nheight = {}\nclear = {:#010X}\n",
                self.width, self.height, self.clear_color
            ),
        )?;
        Ok(path)
    }

    /// Target, states, transform and texture: what `configure` sets, as scene keys.
    fn scene_head(&self) -> String {
        let mut s = format!(
            "format = 1\n\n[target]\nwidth = {}\nheight = {}\nclear = {:#010X}\n",
            self.width, self.height, self.clear_color
        );
        let (src, dst) = match self.kind {
            Kind::W1 | Kind::W2 => ("ONE", "ONE"),
            Kind::W3 | Kind::W4 => ("SRCALPHA", "INVSRCALPHA"),
        };
        let _ = write!(
            s,
            "\n[states]\nPOINTSIZE = {:?}\nLIGHTING = false\nALPHABLENDENABLE = true\n\
             SRCBLEND = \"{src}\"\nDESTBLEND = \"{dst}\"\nZENABLE = {}\nPOINTSPRITEENABLE = {}\n",
            self.point_size,
            self.kind == Kind::W4,
            self.kind != Kind::W1,
        );
        if self.kind == Kind::W4 {
            let aspect = self.width as f32 / self.height as f32;
            let _ = write!(
                s,
                "POINTSCALEENABLE = true\nPOINTSCALE_A = 0.0\nPOINTSCALE_C = 1.0\n\n[transform]\n\
                 projection = {{ perspective_fov_lh = {{ fovy = 0.8, aspect = {aspect:?}, \
                 zn = 1.0, zf = 100.0 }} }}\n"
            );
        }
        if let Some(t) = &self.texture {
            let filter = if self.kind == Kind::W2 {
                "POINT"
            } else {
                "LINEAR"
            };
            let _ = write!(
                s,
                "\n[stage.0]\nMINFILTER = \"{filter}\"\nMAGFILTER = \"{filter}\"\n"
            );
            s.push_str(&inline_texture(t));
        }
        s
    }
}

/// A `[[texture]]` table holding level 0 of `t` inline.
fn inline_texture(t: &Texture) -> String {
    let level = &t.levels()[0];
    let texels: Vec<String> = level.texels.iter().map(|c| format!("{c:#010X}")).collect();
    format!(
        "\n[[texture]]\nstage = 0\nwidth = {}\nheight = {}\ntexels = [{}]\n",
        t.width(),
        t.height(),
        texels.join(", ")
    )
}
