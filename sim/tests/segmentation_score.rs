//! Segmentation scored against the truth (`nudge_sim::metrics::segmentation`): the owners of a
//! look's pixels match its returns, and the score falls when obstacles merge or split objects.

mod world_common;

use nudge_perception::{PerceptionConfig, Prism, detect_from_views};
use nudge_sim::adapter::SimRobot;
use nudge_sim::metrics::segmentation::{LabelledLook, labelled_look, score_look};
use nudge_sim::scenario::Scenario;
use nudge_sim::surface::Owner;

fn paper_room() -> Scenario {
    Scenario::from_toml_str(world_common::KAKIUCHI_ROOM, "kakiuchi_room.toml").expect("loads")
}

fn look_and_detect(scenario: &Scenario) -> (LabelledLook, Vec<Prism>) {
    let mut robot = SimRobot::new(scenario, 1).expect("world");
    let config = PerceptionConfig::default();
    let look = labelled_look(&mut robot, &config).expect("look-around");
    let prisms = detect_from_views(&look.views, &look.base, &config, &[])
        .expect("detects")
        .prisms;
    (look, prisms)
}

#[test]
fn every_return_has_the_owner_of_its_surface_and_only_returns_have_one() {
    // Invariant: a pixel holds a point exactly when the owners name a surface for it, and the points owned by an object lie on or near its true footprint (within the range noise and a cell).
    let scenario = paper_room();
    let (look, _) = look_and_detect(&scenario);
    let mut owned_by_object = 0;
    for (view, owners) in look.views.iter().zip(&look.owners) {
        assert_eq!(owners.len(), view.len());
        let map = nudge_perception::fuse(std::slice::from_ref(view));
        let mut points = map.iter_valid().map(|(_, p, _)| p);
        for (i, owner) in owners.iter().enumerate() {
            let returned = view.point(i).is_some();
            assert_eq!(returned, owner.is_some(), "pixel {i}");
            let Some(p) = returned.then(|| points.next()).flatten() else {
                continue;
            };
            if let Some(Owner::Object(k)) = owner {
                owned_by_object += 1;
                let footprint = scenario.objects[*k]
                    .footprint()
                    .expect("valid size")
                    .polygon();
                let near = nudge_motion::Obstacle::new(
                    nudge_perception::ObjectId(0),
                    &footprint,
                    0.0,
                    1.0,
                )
                .expect("footprint")
                .distance_to_point(&nalgebra::Point2::new(f64::from(p.x), f64::from(p.y)));
                assert!(
                    near < 0.05,
                    "{}: a point {near:.3} m off",
                    scenario.objects[*k].name
                );
            }
        }
    }
    assert!(
        owned_by_object > 1000,
        "{owned_by_object} returns from objects"
    );
}

#[test]
fn merging_two_objects_into_one_obstacle_lowers_their_purity_and_cutting_one_lowers_its_completeness()
 {
    // Invariant: the paper's room scores (near) 1 for the table and chairs as perceived; one obstacle made of the table's and chair-1's loses purity for both, and an obstacle cut in two loses completeness.
    let scenario = paper_room();
    let (look, prisms) = look_and_detect(&scenario);
    let low = PerceptionConfig::default().segment.low_height;
    let score = |prisms: &[Prism], name: &str| {
        score_look(&look, prisms, &scenario, low, 2.0)
            .into_iter()
            .find(|o| o.name == name)
            .expect("seen")
    };
    for name in ["table", "chair-1"] {
        let o = score(&prisms, name);
        assert!(o.purity > 0.97 && o.completeness > 0.95, "{name}: {o:?}");
    }
    // The obstacles holding most of the table's and the chair's returns, merged into one.
    let main = |name: &str| {
        let index = scenario
            .objects
            .iter()
            .position(|o| o.name == name)
            .expect("object");
        let footprint = scenario.objects[index].footprint().expect("size").polygon();
        let iou = |p: &Prism| nudge_perception::prism::convex_iou(&p.footprint, &footprint);
        (0..prisms.len())
            .max_by(|&a, &b| iou(&prisms[a]).total_cmp(&iou(&prisms[b])))
            .expect("obstacles")
    };
    let (t, c) = (main("table"), main("chair-1"));
    let mut merged: Vec<Prism> = prisms
        .iter()
        .enumerate()
        .filter(|(k, _)| *k != t && *k != c)
        .map(|(_, p)| p.clone())
        .collect();
    let mut both = prisms[t].merged_with(&prisms[c]);
    for (_, p, colour) in prisms[c].points.iter_valid() {
        both.points.push(p, colour);
    }
    merged.push(both);
    let (table, chair) = (score(&merged, "table"), score(&merged, "chair-1"));
    assert!(table.purity < 0.9, "table {table:?}");
    assert!(chair.purity < 0.5, "chair-1 {chair:?}");
    // The table's obstacle cut into the points left and right of its middle.
    let table_prism = &prisms[t];
    let mid =
        table_prism.footprint.iter().map(|p| p.x).sum::<f64>() / table_prism.footprint.len() as f64;
    let mut cut: Vec<Prism> = prisms
        .iter()
        .enumerate()
        .filter(|(k, _)| *k != t)
        .map(|(_, p)| p.clone())
        .collect();
    for keep in [|x: f64, m: f64| x < m, |x: f64, m: f64| x >= m] {
        if let Some(half) = table_prism.with_points_where(|p| keep(f64::from(p.x), mid), 0.02) {
            cut.push(half);
        }
    }
    let halved = score(&cut, "table");
    assert!(halved.completeness < 0.75, "table cut in two: {halved:?}");
}
