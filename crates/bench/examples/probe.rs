//! Ad-hoc probe: `cargo run --release -p pointillist-bench --example probe -- w3 2000`.
fn main() {
    let args: Vec<String> = std::env::args().collect();
    let kind = pointillist_bench::workloads::Kind::parse(&args[1]).expect("w1..w4");
    let points = args.get(2).map(|p| p.parse().expect("count"));
    let o = pointillist_bench::BenchOptions {
        kinds: vec![kind],
        points,
        frames: 3,
        llvmpipe: false,
        naive: false,
    };
    pointillist_bench::run(&o, |l| println!("{l}")).expect("bench");
}
