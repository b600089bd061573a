//! OBJ meshes (the `tobj` crate): all models of a file, triangulated, as one
//! [`Mesh`].

use super::malformed;
use crate::error::Result;
use crate::pprt::mesh::Mesh;
use std::path::Path;

/// Reads an OBJ file (a regular file, its size within the memory budget): all its
/// models, triangulated; normals computed when the file lacks any; degenerate triangles
/// dropped and counted ([`Mesh::from_soup`]). `mtllib` lines are ignored (materials come
/// from the scene file; no other file is opened). Errors name the file and the reason.
pub fn read_obj(path: impl AsRef<Path>) -> Result<Mesh> {
    let path = path.as_ref();
    let opts = tobj::LoadOptions {
        triangulate: true,
        single_index: true,
        ..Default::default()
    };
    let bytes = super::input::read_input(path)?;
    // `mtllib` is ignored: materials come from the scene file, and a library path in a
    // hostile OBJ could name any file (or a device) on the machine.
    let no_materials = |_: &Path| Ok((Vec::new(), Default::default()));
    let (models, _) = tobj::load_obj_buf(&mut &bytes[..], &opts, no_materials)
        .map_err(|e| malformed(path, e.to_string()))?;
    let (mut positions, mut normals, mut triangles) = (Vec::new(), Vec::new(), Vec::new());
    let mut all_normals = true;
    for m in &models {
        let base = u32::try_from(positions.len()).unwrap_or(u32::MAX);
        let mesh = &m.mesh;
        positions.extend(
            mesh.positions
                .chunks_exact(3)
                .map(|p| [p[0], p[1], p[2]].map(f64::from)),
        );
        all_normals &= mesh.normals.len() == mesh.positions.len();
        normals.extend(
            mesh.normals
                .chunks_exact(3)
                .map(|p| [p[0], p[1], p[2]].map(f64::from)),
        );
        for t in mesh.indices.chunks_exact(3) {
            // An index past u32 cannot name a vertex: Mesh::from_soup reports it.
            triangles.push([t[0], t[1], t[2]].map(|i| i.saturating_add(base)));
        }
    }
    Mesh::from_soup(positions, all_normals.then_some(normals), triangles)
        .map_err(|e| malformed(path, e.to_string()))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn errors_name_the_file() {
        let e = read_obj("/nonexistent/x.obj").unwrap_err();
        assert!(e.to_string().contains("x.obj"), "{e}");
    }

    /// A quad and a degenerate triangle: two triangles kept, one dropped.
    #[test]
    fn reads_and_drops_degenerate_triangles() {
        let dir = std::env::temp_dir().join(format!("psh-obj-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let p = dir.join("quad.obj");
        std::fs::write(
            &p,
            "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\nf 1 2 2\n",
        )
        .unwrap();
        let m = read_obj(&p).unwrap();
        assert_eq!((m.triangles().len(), m.dropped()), (2, 1));
        assert!(m.normals().iter().all(|n| (n[2] - 1.0).abs() < 1e-15));
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
