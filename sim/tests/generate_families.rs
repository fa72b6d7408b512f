//! `nudge generate`'s families: the same seed writes the same files, every file loads through the
//! scenario loader, and every family's guarantee and promises hold in the true world.

use nudge_sim::generate::{
    Family, Generated, Guarantee, NeededPush, PushKind, check_pushes, generate, generate_one,
    to_toml,
};
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
                Guarantee::WayExists | Guarantee::WayNeedsEach(_) => {
                    panic!("{}: a door family has one blocker", s.name)
                }
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
        Family::Touching => touching_promises(s, guarantee),
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

/// `touching`: every blocker stands within 3 cm of what it is against or turned in a doorway with
/// 3–10 cm to spare, and the pushes its file names can be made on the reloaded true world.
fn touching_promises(s: &Scenario, guarantee: &Guarantee) {
    let blockers: Vec<&str> = match guarantee {
        Guarantee::WayNeeds(n) | Guarantee::ShutBy(n) => vec![n.as_str()],
        Guarantee::WayNeedsEach(names) => names.iter().map(String::as_str).collect(),
        Guarantee::WayExists => panic!("{}: a touching room always has a blocker", s.name),
    };
    let kind = match guarantee {
        Guarantee::ShutBy(_) => PushKind::Test,
        _ => PushKind::Clear,
    };
    for name in &blockers {
        let b = s.objects.iter().find(|o| &o.name == name).expect("blocker");
        // Its nearest other thing (a wall, a jamb, a cabinet, the other box) within 10 cm: nothing
        // of this family stands in the open.
        let gap = nearest_gap(s, b);
        assert!(
            gap <= 0.10 + 1e-6,
            "{}: `{name}` {gap:.3} m from anything",
            s.name
        );
    }
    let needs: Vec<NeededPush> = blockers
        .iter()
        .map(|name| NeededPush {
            object: name.to_string(),
            direction: direction_of(s, name),
            kind,
        })
        .collect();
    let made = check_pushes(s, &needs).expect("world builds");
    assert!(made.is_some(), "{}: its pushes cannot be made", s.name);
}

/// The way a touching room's blocker is pushed: along the partition for the low box, else east.
fn direction_of(s: &Scenario, name: &str) -> [f64; 2] {
    if name != "low-box" {
        return [1.0, 0.0];
    }
    let b = s.objects.iter().find(|o| o.name == name).expect("low box");
    let south_jamb = s
        .objects
        .iter()
        .find(|o| o.name == "wall-south")
        .map_or(0.0, |w| w.position[1] + w.size[1] / 2.0);
    // A box straddling the south jamb goes south, one straddling the north jamb goes north.
    if b.position[1] < south_jamb + b.size[1] / 2.0 {
        [0.0, -1.0]
    } else {
        [0.0, 1.0]
    }
}

/// The smallest gap between `b`'s axis-aligned box (turned boxes: the box around them) and the
/// room's walls or any other object's axis-aligned box (m).
fn nearest_gap(s: &Scenario, b: &nudge_sim::scenario::ObjectSpec) -> f64 {
    let half = |o: &nudge_sim::scenario::ObjectSpec| {
        let t = o.yaw.to_radians();
        let (c, sn) = (t.cos().abs(), t.sin().abs());
        [
            (o.size[0] * c + o.size[1] * sn) / 2.0,
            (o.size[0] * sn + o.size[1] * c) / 2.0,
        ]
    };
    let hb = half(b);
    let [w, h] = s.room.size;
    let mut gap = (b.position[0] - hb[0])
        .min(w - b.position[0] - hb[0])
        .min(b.position[1] - hb[1])
        .min(h - b.position[1] - hb[1]);
    for o in s.objects.iter().filter(|o| o.name != b.name) {
        let ho = half(o);
        let dx = (o.position[0] - b.position[0]).abs() - ho[0] - hb[0];
        let dy = (o.position[1] - b.position[1]).abs() - ho[1] - hb[1];
        gap = gap.min(dx.max(dy));
    }
    gap
}

#[test]
fn a_push_whose_sweep_runs_into_a_bolted_post_cannot_be_made() {
    // Invariant: the touching family's push check refuses a clearing push whose object would have to pass through a bolted post 20 cm across (small enough that the robot could walk round it), and accepts the push without the post.
    let g = (0..)
        .map(|i| generate_one(Family::Touching, 3, i).expect("generates"))
        .find(|g| {
            matches!(g.guarantee, Guarantee::WayNeeds(_))
                && g.pushes
                    .first()
                    .is_some_and(|p| p.push.direction == [1.0, 0.0])
        })
        .expect("a room whose blocker is pushed east");
    let push = g.pushes[0].push.clone();
    let mut s = g.scenario.clone();
    let blocker = s
        .objects
        .iter()
        .find(|o| o.name == push.object)
        .expect("blocker")
        .clone();
    assert!(
        check_pushes(&s, std::slice::from_ref(&push))
            .expect("builds")
            .is_some()
    );
    // A bolted post on the blocker's way east, 0.8 m on.
    let mut post = blocker.clone();
    post.name = "in-the-way".into();
    post.fixed = true;
    post.yaw = 0.0;
    post.size = vec![0.2, 0.2, 1.0];
    post.position = [blocker.position[0] + 0.8, blocker.position[1]];
    s.objects.push(post);
    assert!(
        check_pushes(&s, std::slice::from_ref(&push))
            .expect("builds")
            .is_none(),
        "{}: the sweep runs into the post",
        s.name
    );
}
