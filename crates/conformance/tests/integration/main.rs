//! The conformance suite, one module per chapter of `docs/spec/SPEC.md` (sections 2 to 9), the
//! cases restated from Wine's visual tests, the golden scenes and the property tests.
//!
//! Each case is a scene file under `crates/conformance/cases/` (its README describes the
//! layout and docs/spec/SCENE.md the `[case]` table), run by one test of the same name on every
//! backend (`run::run_case`). API behaviour a scene cannot state (state
//! read-back, validation errors, notices) is tested in Rust beside the cases of its chapter, with
//! the programmatic scenes that compare the GPU backend with the CPU backend per rule family
//! (`pointillist_testkit::check`: exact where no filtering or blending arithmetic is involved,
//! within 1/255 per channel otherwise).

mod common;
mod run;

/// One test per case file of `cases/$folder` (named after the file), and
/// `every_case_file_has_a_test`, which fails when the folder holds a file the list lacks or
/// the list names a file the folder lacks.
macro_rules! cases {
    ($folder:literal: $($name:ident),* $(,)?) => {
        $(
            #[test]
            fn $name() {
                crate::common::case($folder, stringify!($name));
            }
        )*

        #[test]
        fn every_case_file_has_a_test() {
            crate::common::folder_holds($folder, &[$(stringify!($name)),*]);
        }
    };
}

mod caps;
mod clipping;
mod fog;
mod golden;
mod lighting;
mod pixels;
mod properties;
mod rasterization;
mod size;
mod suite;
mod wine;
