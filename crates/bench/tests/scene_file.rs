//! The workloads written as scene files draw what the workloads draw in process, so that
//! `pointillist bench --end-to-end` times the same pixels as `pointillist bench`.

use pointillist_bench::workloads::{Kind, Workload};

#[test]
fn each_workloads_scene_file_renders_its_frame_exactly() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path().to_path_buf();
    for kind in Kind::ALL {
        let w = Workload::new(kind, 2_000);
        let mut device = pointillist_cpu::device(w.device_desc()).unwrap();
        w.configure(&mut device).unwrap();
        device.clear(w.clear_color, 1.0).unwrap();
        device.draw_point_list(w.fvf, &w.vertices).unwrap();
        let expected = device.read_target().unwrap();

        let path = w.write_scene(&dir).unwrap();
        let scene = pointillist_scene::load(&path).unwrap();
        let mut device = pointillist_cpu::device(scene.device_desc()).unwrap();
        scene.replay(&mut device).unwrap();
        let actual = device.read_target().unwrap();
        assert_eq!(actual.to_rgba8(), expected.to_rgba8(), "{kind:?}");
        assert!(
            expected
                .to_rgba8()
                .chunks_exact(4)
                .any(|p| p[..3] != [0, 0, 0]),
            "{kind:?} draws something"
        );

        let empty = pointillist_scene::load(&w.write_empty_scene(&dir).unwrap()).unwrap();
        assert_eq!(empty.draw_count(), 0);
        assert_eq!(
            (empty.target.width, empty.target.height),
            (w.width, w.height)
        );
    }
}
