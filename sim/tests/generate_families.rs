//! `nudge generate`'s families: the same seed writes the same files, every file loads through the
//! scenario loader, and every family's guarantee and promises hold in the true world.

use nudge_sim::generate::{Family, Generated, Guarantee, generate, generate_one, to_toml};
use nudge_sim::scenario::{ExpectedOutcome, GRAVITY, Scenario};
use nudge_sim::truth::MOVABLE_MARGIN;

/// Scenarios checked per family: enough to meet every branch of each family's draws.
const PER_FAMILY: usize = 12;

fn reload(g: &Generated) -> Scenario {
    let text = to_toml(g).expect("serialises");
    Scenario::from_toml_str(&text, "generated").expect("a generated file loads and validates")
}

#[test]
fn every_family_writes_the_same_files_for_the_same_seed() {
    // Invariant: same family, seed and count give byte-identical files; scenario k does not depend on how many are made; another seed gives other rooms.
    for family in Family::ALL {
        let a: Vec<String> = generate(family, 7, 4)
            .expect("generates")
            .iter()
            .map(|g| to_toml(g).expect("toml"))
            .collect();
        let b: Vec<String> = generate(family, 7, 4)
            .expect("generates")
            .iter()
            .map(|g| to_toml(g).expect("toml"))
            .collect();
        assert_eq!(a, b, "{family}");
        let third = to_toml(&generate_one(family, 7, 2).expect("one")).expect("toml");
        assert_eq!(a[2], third, "{family}: index 2 alone");
        let other = to_toml(&generate_one(family, 8, 0).expect("one")).expect("toml");
        assert_ne!(a[0], other, "{family}: seed 8 differs from seed 7");
    }
}

#[test]
fn every_generated_scenario_keeps_its_guarantee_in_the_true_world() {
    // Invariant: each file loads, its [expect] block is its guarantee's, and the guarantee holds on the reloaded file's true world (ideal paths with movable objects taken away, the blocker bolted or removed).
    for family in Family::ALL {
        for g in generate(family, 1, PER_FAMILY).expect("generates") {
            let s = reload(&g);
            assert_eq!(s.family.as_deref(), Some(family.name()));
            assert_eq!(s.expect.as_ref(), Some(&g.guarantee.expect()), "{}", s.name);
            assert!(
                g.guarantee.holds(&s).expect("world builds"),
                "{}: {}",
                s.name,
                g.guarantee
            );
            promises(family, &s, &g.guarantee);
        }
    }
}

/// Each family's own promises, read off the scenario against the robot, sensor and truth.
fn promises(family: Family, s: &Scenario, guarantee: &Guarantee) {
    let start = [s.robot.start[0], s.robot.start[1]];
    let distance = (s.goal.position[0] - start[0]).hypot(s.goal.position[1] - start[1]);
    let robot_width = 2.0 * s.robot.radius();
    let slide = |name: &str| {
        let o = s
            .objects
            .iter()
            .find(|o| o.name == name)
            .expect("named object");
        (o.friction * o.mass * GRAVITY, o.fixed)
    };
    match family {
        Family::LargeRoom => {
            // The colour range sensor sees 5 m: the goal lies beyond one look from the start.
            assert!(distance >= 8.0, "{}: goal {distance:.2} m away", s.name);
        }
        Family::BlockedDoor | Family::ForceLimit => {
            let (force, fixed) = slide("door-box");
            match guarantee {
                Guarantee::WayNeeds(_) => {
                    assert!(
                        !fixed && force < MOVABLE_MARGIN * push_limit(),
                        "{}",
                        s.name
                    )
                }
                Guarantee::ShutBy(_) => assert!(fixed || force >= push_limit(), "{}", s.name),
                Guarantee::WayExists => panic!("{}: a door family always has a blocker", s.name),
            }
            if family == Family::ForceLimit {
                // 0.5–1.5 × the limit, never in the band the truth does not score.
                assert!((10.0..=30.0).contains(&force), "{}: {force:.2} N", s.name);
                assert!(
                    !(MOVABLE_MARGIN * push_limit()..push_limit()).contains(&force),
                    "{}: {force:.2} N in the unscored band",
                    s.name
                );
            }
            let part = |name: &str| s.objects.iter().find(|o| o.name == name).expect(name);
            let (south, north) = (part("wall-0-south"), part("wall-0-north"));
            let door = [
                south.position[1] + south.size[1] / 2.0,
                north.position[1] - north.size[1] / 2.0,
            ];
            let b = part("door-box");
            // The box leaves less than the robot's width on either side of it in the door.
            let beside = [
                b.position[1] - b.size[1] / 2.0 - door[0],
                door[1] - b.position[1] - b.size[1] / 2.0,
            ];
            assert!(
                beside.iter().all(|g| *g < robot_width),
                "{}: {beside:?}",
                s.name
            );
        }
        Family::Overhang => {
            let shelf = s.objects.iter().find(|o| o.name == "shelf").expect("shelf");
            assert!(shelf.elevation > s.robot.height(), "{}", s.name);
            assert!(
                shelf.size[1] >= s.room.size[1] - 0.05,
                "{}: spans the room",
                s.name
            );
            assert_eq!(guarantee, &Guarantee::WayExists);
        }
        Family::Wanderers => {
            assert!(s.actors.len() <= 10, "{}", s.name);
            assert_eq!(guarantee, &Guarantee::WayExists);
        }
        Family::Corridor => {
            assert!(matches!(
                guarantee,
                Guarantee::WayExists | Guarantee::WayNeeds(_)
            ));
        }
        Family::Flat => {
            let walls = s
                .objects
                .iter()
                .filter(|o| o.name.starts_with("wall-"))
                .count();
            assert!(
                (1..=6).contains(&walls),
                "{}: {walls} partition pieces",
                s.name
            );
            assert_eq!(guarantee, &Guarantee::WayExists);
        }
        Family::OpenClutter => assert_eq!(guarantee, &Guarantee::WayExists),
    }
    if let Some(e) = &s.expect {
        let expect_goal = !matches!(guarantee, Guarantee::ShutBy(_));
        assert_eq!(
            e.outcome == ExpectedOutcome::Goal,
            expect_goal,
            "{}",
            s.name
        );
    }
}

/// The push-test limit of the default robot, which generated rooms carry (N).
fn push_limit() -> f64 {
    nudge_robot_model::ForceModel::default().test_limit
}
