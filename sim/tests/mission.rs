//! The mission supervisor driving the farm with obstacles (EM-SIM-MISSION-*).

use fieldguide_sim::guiding::mission::{drive_mission, summary_json, welaser_mission};

#[test]
fn print_one() {
    let run = welaser_mission(1).expect("built-in");
    let o = drive_mission(&run);
    println!(
        "{}",
        serde_json::to_string_pretty(&summary_json(&run, &o)).unwrap()
    );
    for s in &o.stops {
        println!("{s:?}");
    }
    for r in &o.replans {
        println!("{r:?}");
    }
    fieldguide_sim::guiding::mission::write(std::path::Path::new("/tmp/wm"), &run, &o).unwrap();
}
