//! Colour ICP after Park, Zhou & Koltun, "Colored Point Cloud Registration Revisited" (ICCV 2017).
//!
//! **Why Park et al. and not Johnson & Kang (1997).** Johnson & Kang add colour to the nearest-neighbour
//! search (6-D points) but still minimise a purely geometric error, so colour only helps to *pick*
//! correspondences; with a point-to-plane error (which we want for millimetre accuracy) a slide along a
//! flat face stays invisible, and with a point-to-point error the accuracy is bounded by the sampling.
//! Park et al. minimise a joint objective: point-to-plane distance *plus* the difference between the
//! source point's intensity and the target's intensity continued along the target's tangent plane by a
//! locally fitted colour gradient. The photometric term pins exactly the motions geometry cannot see
//! (a textured panel slid along itself, a box turned about its own axis), the geometric term keeps
//! sub-millimetre accuracy where there is shape, and the correspondences stay cheap 3-D nearest
//! neighbours (kiddo).
//!
//! **Robustness to partial overlap** (the arm, or the object itself, hides different points before and
//! after): correspondences are trimmed by a shrinking distance schedule (coarse stages tolerate a poor
//! initial guess, fine stages drop points with no counterpart), and each residual gets a Huber weight.
//!
//! **Determinism**: sums run over fixed-size chunks in parallel and are added in chunk order, so the
//! result is the same bit for bit whatever the thread count.

use nalgebra::{
    Isometry3, Matrix3, Matrix6, Point3, Translation3, UnitQuaternion, Vector3, Vector6,
};
use std::sync::OnceLock;

use rayon::prelude::*;

use crate::cloud::ColourCloud;
use crate::error::PerceptionError;
use crate::icp::kdtree::PointTree;
use crate::icp::result::IcpResult;

/// Parameters of colour ICP.
#[derive(Clone, Debug, PartialEq)]
pub struct IcpConfig {
    /// Greatest correspondence distance of each stage (m), coarse to fine. Default
    /// [0.25, 0.12, 0.06, 0.03, 0.012]: the first stage tolerates an initial guess ~20 cm off, the
    /// last keeps only points within a few noise widths of the target surface.
    pub max_correspondence: Vec<f64>,
    /// Stages whose distance bound is above this (m) solve only the planar motion (x, y, yaw) and use
    /// geometry only: far from alignment the colour gradients (local by nature) add noise, and a push on
    /// the floor is planar, so the coarse stages cannot tumble the object into a wrong basin. Finer
    /// stages solve all six degrees of freedom with colour. Default 0.05.
    pub planar_above: f64,
    /// Directions of the normal equations whose eigenvalue is below this fraction of the largest are
    /// not updated (degeneracy-aware solve, Zhang et al. 2016): what the data cannot see (a slide along
    /// a plane without colour) stays where the guess put it instead of drifting on noise. Default 1e-3.
    pub degeneracy_ratio: f64,
    /// In a coarse (planar) stage, when the smaller eigenvalue of the geometric normal equations'
    /// floor-plane translation block is below this fraction of the larger, geometry cannot see one
    /// horizontal direction (a flat face) and the photometric term is switched on for that stage.
    /// Default 0.05.
    pub flat_geometry_ratio: f64,
    /// Most Gauss–Newton iterations per stage. Default 12.
    pub max_iterations_per_stage: usize,
    /// Weight λ of the geometric term (the photometric one gets 1 − λ). Default 0.968 (Park et al.'s
    /// value, with intensities in 0–1 and distances in m).
    pub lambda_geometric: f64,
    /// Use the photometric term. `false` gives plain point-to-plane ICP (for comparison). Default true.
    pub photometric: bool,
    /// Neighbours for the target's normals and colour gradients. Default 12.
    pub neighbours: usize,
    /// Source points used in the fine stages (an even stride through the cloud beyond this).
    /// Default 1600: residual noise averages out well below a millimetre at that count.
    pub max_source_points: usize,
    /// Source points used in the coarse (planar) stages. Default 600: they only need to find the
    /// basin.
    pub max_coarse_source_points: usize,
    /// Target points kept (an even stride beyond this) for correspondences, normals and colour
    /// gradients. Default 5000: the point-to-plane and photometric terms use the local plane, not the
    /// point, so a sparser target costs little accuracy and saves most of the preparation time.
    pub max_target_points: usize,
    /// Huber threshold of the geometric residual (m). Default 0.005.
    pub huber_geometric: f64,
    /// Huber threshold of the photometric residual (intensity, 0–1). Default 0.1.
    pub huber_photometric: f64,
    /// A stage ends when the update's translation is below this (m). Default 2e-4 (0.2 mm): a tenth of
    /// the accuracy asked of a push reading, yet above the last stage's jitter on a ToF camera's noise.
    pub converge_translation: f64,
    /// … and its rotation below this (rad). Default 2e-4 (0.011°).
    pub converge_rotation: f64,
    /// Fewest valid points per cloud. Default 20.
    pub min_points: usize,
    /// Fewest correspondences for an update. Default 10.
    pub min_correspondences: usize,
}

impl Default for IcpConfig {
    fn default() -> Self {
        Self {
            max_correspondence: vec![0.25, 0.12, 0.06, 0.03, 0.012],
            planar_above: 0.05,
            degeneracy_ratio: 1e-3,
            flat_geometry_ratio: 0.05,
            max_iterations_per_stage: 12,
            lambda_geometric: 0.968,
            photometric: true,
            neighbours: 12,
            max_source_points: 1600,
            max_coarse_source_points: 600,
            max_target_points: 5000,
            huber_geometric: 0.005,
            huber_photometric: 0.1,
            converge_translation: 2e-4,
            converge_rotation: 2e-4,
            min_points: 20,
            min_correspondences: 10,
        }
    }
}

impl IcpConfig {
    /// Plain point-to-plane ICP (no photometric term), otherwise the defaults.
    pub fn geometric_only() -> Self {
        Self {
            photometric: false,
            ..Self::default()
        }
    }
}

/// The initial guess that moves the source centroid onto the target centroid (no rotation), for when
/// nothing better is known. `None` when either cloud has no valid point.
pub fn initial_from_centroids(
    source: &ColourCloud,
    target: &ColourCloud,
) -> Option<Isometry3<f64>> {
    let (s, t) = (source.centroid()?, target.centroid()?);
    Some(Isometry3::from_parts(
        Translation3::from(t - s),
        UnitQuaternion::identity(),
    ))
}

/// What the target knows around one of its points.
struct Local {
    normal: Vector3<f64>,
    gradient: Vector3<f64>,
    /// A quarter of the squared distance to the nearest other target point: a query closer than
    /// that to this point has it as its exact nearest neighbour (see [`Target::nearest_reusing`]).
    half_gap_sq: f32,
}

/// No correspondence remembered for a source point.
const NONE: u32 = u32::MAX;

/// The target side: points (centred), normals, intensities, colour gradients, and their k-d tree.
struct Target {
    points: Vec<[f32; 3]>,
    intensity: Vec<f64>,
    local: Vec<OnceLock<Local>>,
    k: usize,
    photometric: bool,
    tree: PointTree,
}

/// Estimates the motion of an object from its points `source` (before the push) to `target` (after),
/// both in the map frame, starting from `initial` (e.g. the hand's travel; see
/// [`initial_from_centroids`] when nothing is known).
///
/// Errors: too few valid points in either cloud, a non-finite guess, or too few correspondences at the
/// first stage (the guess is far off or the clouds show different objects).
pub fn colour_icp(
    source: &ColourCloud,
    target: &ColourCloud,
    initial: &Isometry3<f64>,
    config: &IcpConfig,
) -> Result<IcpResult, PerceptionError> {
    let (src_all, src_int_all) = valid_points(source);
    let (tgt_pts, tgt_int) = valid_points(target);
    let needed = config.min_points.max(config.neighbours.max(3));
    if src_all.len() < needed || tgt_pts.len() < needed {
        return Err(PerceptionError::TooFewIcpPoints {
            source_count: src_all.len(),
            target_count: tgt_pts.len(),
            needed,
        });
    }
    if !(initial.translation.vector.iter().all(|v| v.is_finite())
        && initial.rotation.coords.iter().all(|v| v.is_finite()))
    {
        return Err(PerceptionError::InvalidInput(
            "initial guess is not finite".into(),
        ));
    }
    // Work in coordinates centred on the source centroid: well-conditioned rotations, f32-safe.
    let centre = centroid(&src_all);
    let to_centred = Translation3::from(-centre.coords);
    let subsample = |max: usize| {
        let stride = src_all.len().div_ceil(max.max(1));
        let pts: Vec<Vector3<f64>> = src_all
            .iter()
            .step_by(stride)
            .map(|p| p.coords - centre.coords)
            .collect();
        let int: Vec<f64> = src_int_all.iter().step_by(stride).copied().collect();
        (pts, int)
    };
    let fine = subsample(config.max_source_points);
    let coarse = subsample(config.max_coarse_source_points);
    let t_stride = tgt_pts.len().div_ceil(config.max_target_points.max(needed));
    let tgt_pts: Vec<Point3<f64>> = tgt_pts.into_iter().step_by(t_stride).collect();
    let tgt_int: Vec<f64> = tgt_int.into_iter().step_by(t_stride).collect();
    let target = prepare_target(&tgt_pts, &tgt_int, &centre, config);

    let mut motion = to_centred * initial * to_centred.inverse();
    // Each source point's last correspondence, for `Target::nearest_reusing`.
    let mut coarse_last = vec![NONE; coarse.0.len()];
    let mut fine_last = vec![NONE; fine.0.len()];
    let mut iterations = 0;
    let mut converged = false;
    for (stage, &max_dist) in config.max_correspondence.iter().enumerate() {
        converged = false;
        let planar = max_dist > config.planar_above;
        let dofs: &[usize] = if planar {
            &[2, 3, 4]
        } else {
            &[0, 1, 2, 3, 4, 5]
        };
        let (src, src_int) = if planar {
            (&coarse.0, &coarse.1)
        } else {
            (&fine.0, &fine.1)
        };
        for _ in 0..config.max_iterations_per_stage {
            let last = if planar {
                &mut coarse_last
            } else {
                &mut fine_last
            };
            let mut system = linearise(
                src, src_int, last, &target, &motion, max_dist, !planar, config,
            );
            if planar && config.photometric && planar_geometry_is_degenerate(&system.jtj, config) {
                // Geometry cannot hold the floor-plane translation (a flat face): colour must drive
                // the coarse stages too, or the coarse alignment drifts on noise and window edges.
                system = linearise(src, src_int, last, &target, &motion, max_dist, true, config);
            }
            if system.count < config.min_correspondences {
                if stage == 0 && iterations == 0 {
                    return Err(PerceptionError::TooFewCorrespondences {
                        found: system.count,
                        needed: config.min_correspondences,
                    });
                }
                break;
            }
            iterations += 1;
            let Some(step) = solve(&system.jtj, &system.jtr, dofs, config.degeneracy_ratio) else {
                break;
            };
            let rotation = UnitQuaternion::from_scaled_axis(step.fixed_rows::<3>(0).into_owned());
            let translation = Vector3::from(step.fixed_rows::<3>(3));
            motion = Isometry3::from_parts(Translation3::from(translation), rotation) * motion;
            if translation.norm() < config.converge_translation
                && rotation.angle() < config.converge_rotation
            {
                converged = true;
                break;
            }
        }
    }
    let final_dist = config.max_correspondence.last().copied().unwrap_or(0.05);
    let (fitness, rmse) = quality(&fine.0, &mut fine_last, &target, &motion, final_dist);
    let map_motion = to_centred.inverse() * motion * to_centred;
    Ok(IcpResult::from_motion(
        map_motion, &centre, fitness, rmse, iterations, converged,
    ))
}

fn valid_points(cloud: &ColourCloud) -> (Vec<Point3<f64>>, Vec<f64>) {
    cloud
        .iter_valid()
        .map(|(_, p, c)| (p.cast::<f64>(), intensity(c)))
        .unzip()
}

fn intensity(c: [u8; 3]) -> f64 {
    (f64::from(c[0]) + f64::from(c[1]) + f64::from(c[2])) / (3.0 * 255.0)
}

fn centroid(points: &[Point3<f64>]) -> Point3<f64> {
    let sum: Vector3<f64> = points.iter().map(|p| p.coords).sum();
    Point3::from(sum / points.len().max(1) as f64)
}

/// Normals by principal components of the k nearest neighbours; colour gradients by least squares on
/// the tangent plane (Park et al. eq. 10, with the gradient held orthogonal to the normal). Both are
/// computed lazily, the first time a target point is a correspondence (most never are), and cached; the
/// value is a pure function of the target, so laziness does not affect determinism.
fn prepare_target(
    points: &[Point3<f64>],
    intensity: &[f64],
    centre: &Point3<f64>,
    config: &IcpConfig,
) -> Target {
    let centred: Vec<[f32; 3]> = points
        .iter()
        .map(|p| {
            let v = p - centre;
            [v.x as f32, v.y as f32, v.z as f32]
        })
        .collect();
    let tree = PointTree::new(&centred);
    let local = (0..centred.len()).map(|_| OnceLock::new()).collect();
    Target {
        points: centred,
        intensity: intensity.to_vec(),
        local,
        k: config.neighbours.max(3),
        photometric: config.photometric,
        tree,
    }
}

impl Target {
    /// Normal, colour gradient and nearest-point gap of target point `i`.
    fn local(&self, i: usize) -> &Local {
        self.local[i].get_or_init(|| self.compute_local(i))
    }

    /// The nearest target point to `q` (index, squared distance), skipping the tree query when the
    /// source point's previous correspondence `*last` provably still is the nearest: if
    /// |q − t_j| < r_j / 2, with r_j the distance from t_j to its nearest other target point, every
    /// other point is farther than r_j / 2 (triangle inequality). Between Gauss–Newton iterations a
    /// point moves far less than the sampling gap, so most queries are answered this way. The answer
    /// is the exact nearest neighbour either way (the margin below keeps f32 rounding from flipping a
    /// near-tie), so the result does not depend on which path was taken.
    fn nearest_reusing(&self, q: &[f32; 3], last: &mut u32, max_sq: f32) -> Option<(usize, f32)> {
        let j = *last as usize;
        if let Some(local) = self.local.get(j).and_then(OnceLock::get) {
            let t = self.points[j];
            let d2 = (q[0] - t[0]).powi(2) + (q[1] - t[1]).powi(2) + (q[2] - t[2]).powi(2);
            if d2 < 0.96 * local.half_gap_sq && d2 < 0.99 * max_sq {
                return Some((j, d2));
            }
        }
        let hit = self.tree.nearest(q)?;
        *last = u32::try_from(hit.0).unwrap_or(NONE);
        Some(hit)
    }

    fn at(&self, j: usize) -> Vector3<f64> {
        let p = self.points[j];
        Vector3::new(f64::from(p[0]), f64::from(p[1]), f64::from(p[2]))
    }

    fn compute_local(&self, i: usize) -> Local {
        let nn = self.tree.nearest_k(&self.points[i], self.k);
        let gap_sq = nn
            .iter()
            .filter(|&&(j, _)| j != i)
            .map(|&(_, d2)| d2)
            .fold(f32::INFINITY, f32::min);
        let half_gap_sq = if gap_sq.is_finite() {
            gap_sq / 4.0
        } else {
            0.0
        };
        let here = self.at(i);
        let mean: Vector3<f64> =
            nn.iter().map(|&(j, _)| self.at(j)).sum::<Vector3<f64>>() / nn.len().max(1) as f64;
        let mut cov = Matrix3::zeros();
        for &(j, _) in &nn {
            let d = self.at(j) - mean;
            cov += d * d.transpose();
        }
        let normal = smallest_eigenvector(&cov).unwrap_or_else(|| {
            let eig = cov.symmetric_eigen();
            let v = eig.eigenvectors.column(eig.eigenvalues.imin()).into_owned();
            if v.norm() > 0.0 {
                v.normalize()
            } else {
                Vector3::z()
            }
        });
        let gradient = if self.photometric {
            colour_gradient(
                here,
                self.intensity[i],
                &normal,
                &nn,
                &|j| self.at(j),
                &self.intensity,
            )
        } else {
            Vector3::zeros()
        };
        Local {
            normal,
            gradient,
            half_gap_sq,
        }
    }
}

/// Unit eigenvector of the smallest eigenvalue of a symmetric 3×3 matrix, in closed form (Smith's
/// trigonometric eigenvalues, then the best-conditioned cross product of two rows of `A − λI`); about
/// ten times faster than the iterative solver. `None` when the matrix is (near) isotropic or degenerate,
/// for the caller to fall back on the iterative solver.
fn smallest_eigenvector(a: &Matrix3<f64>) -> Option<Vector3<f64>> {
    let p1 = a[(0, 1)].powi(2) + a[(0, 2)].powi(2) + a[(1, 2)].powi(2);
    let q = a.trace() / 3.0;
    let p2 = (a[(0, 0)] - q).powi(2) + (a[(1, 1)] - q).powi(2) + (a[(2, 2)] - q).powi(2) + 2.0 * p1;
    let p = (p2 / 6.0).sqrt();
    if !(p.is_finite() && p > 1e-12 * q.abs().max(1e-300)) {
        return None;
    }
    let b = (a - Matrix3::identity() * q) / p;
    let r = (b.determinant() / 2.0).clamp(-1.0, 1.0);
    let phi = r.acos() / 3.0;
    let lambda = q + 2.0 * p * (phi + 2.0 * std::f64::consts::PI / 3.0).cos();
    let m = a - Matrix3::identity() * lambda;
    let (r0, r1, r2) = (
        m.row(0).transpose(),
        m.row(1).transpose(),
        m.row(2).transpose(),
    );
    let candidates = [r0.cross(&r1), r0.cross(&r2), r1.cross(&r2)];
    let best = candidates
        .iter()
        .max_by(|x, y| x.norm_squared().total_cmp(&y.norm_squared()))?;
    let n = best.norm();
    (n.is_finite() && n > 1e-9 * p * p).then(|| best / n)
}

fn colour_gradient(
    here: Vector3<f64>,
    here_intensity: f64,
    normal: &Vector3<f64>,
    neighbours: &[(usize, f32)],
    at: &impl Fn(usize) -> Vector3<f64>,
    intensity: &[f64],
) -> Vector3<f64> {
    let mut ata = Matrix3::zeros();
    let mut atb = Vector3::zeros();
    for &(j, _) in neighbours {
        let d = at(j) - here;
        let on_plane = d - normal * normal.dot(&d);
        ata += on_plane * on_plane.transpose();
        atb += on_plane * (intensity[j] - here_intensity);
    }
    // The constraint gradient · normal = 0, weighted like the neighbours together.
    let w = (neighbours.len().saturating_sub(1)) as f64;
    ata += normal * normal.transpose() * w;
    ata.try_inverse()
        .map_or_else(Vector3::zeros, |inv| inv * atb)
}

struct System {
    jtj: Matrix6<f64>,
    jtr: Vector6<f64>,
    count: usize,
}

const CHUNK: usize = 256;

#[allow(clippy::too_many_arguments)]
fn linearise(
    src: &[Vector3<f64>],
    src_int: &[f64],
    last: &mut [u32],
    target: &Target,
    motion: &Isometry3<f64>,
    max_dist: f64,
    with_colour: bool,
    config: &IcpConfig,
) -> System {
    let max_sq = (max_dist * max_dist) as f32;
    let (lg, lp) = if config.photometric && with_colour {
        (config.lambda_geometric, 1.0 - config.lambda_geometric)
    } else {
        (1.0, 0.0)
    };
    let rot = motion.rotation.to_rotation_matrix().into_inner();
    let shift = motion.translation.vector;
    let partial: Vec<System> = src
        .par_chunks(CHUNK)
        .zip(last.par_chunks_mut(CHUNK))
        .enumerate()
        .map(|(c, (chunk, last))| {
            let mut s = System {
                jtj: Matrix6::zeros(),
                jtr: Vector6::zeros(),
                count: 0,
            };
            for (o, (p, last)) in chunk.iter().zip(last.iter_mut()).enumerate() {
                let i = c * CHUNK + o;
                let ps = Point3::from(rot * p + shift);
                let q32 = [ps.x as f32, ps.y as f32, ps.z as f32];
                let Some((j, d2)) = target.nearest_reusing(&q32, last, max_sq) else {
                    continue;
                };
                if d2 > max_sq {
                    continue;
                }
                let t = target.points[j];
                let vt = Vector3::new(f64::from(t[0]), f64::from(t[1]), f64::from(t[2]));
                let local = target.local(j);
                let (n, d) = (local.normal, local.gradient);
                let vs = ps.coords;
                let diff = vs - vt;
                // Geometric: point-to-plane.
                let rg = diff.dot(&n);
                let mut jg = Vector6::zeros();
                jg.fixed_rows_mut::<3>(0).copy_from(&vs.cross(&n));
                jg.fixed_rows_mut::<3>(3).copy_from(&n);
                let wg = lg * huber_weight(rg, config.huber_geometric);
                s.jtj.ger(wg, &jg, &jg, 1.0);
                s.jtr += jg * (rg * wg);
                if lp > 0.0 {
                    // Photometric: source intensity vs the target's, continued along its tangent plane.
                    let proj = vs - n * rg;
                    let predicted = target.intensity[j] + d.dot(&(proj - vt));
                    let rc = src_int[i] - predicted;
                    let g = -(d - n * n.dot(&d));
                    let mut jc = Vector6::zeros();
                    jc.fixed_rows_mut::<3>(0).copy_from(&vs.cross(&g));
                    jc.fixed_rows_mut::<3>(3).copy_from(&g);
                    let wc = lp * huber_weight(rc, config.huber_photometric);
                    s.jtj.ger(wc, &jc, &jc, 1.0);
                    s.jtr += jc * (rc * wc);
                }
                s.count += 1;
            }
            s
        })
        .collect();
    partial.into_iter().fold(
        System {
            jtj: Matrix6::zeros(),
            jtr: Vector6::zeros(),
            count: 0,
        },
        |mut a, b| {
            a.jtj += b.jtj;
            a.jtr += b.jtr;
            a.count += b.count;
            a
        },
    )
}

/// True when the geometric system barely constrains one horizontal translation direction.
fn planar_geometry_is_degenerate(jtj: &Matrix6<f64>, config: &IcpConfig) -> bool {
    let block = nalgebra::Matrix2::new(jtj[(3, 3)], jtj[(3, 4)], jtj[(4, 3)], jtj[(4, 4)]);
    let eig = block.symmetric_eigenvalues();
    let (lo, hi) = (eig.min(), eig.max());
    hi > 0.0 && lo < config.flat_geometry_ratio * hi
}

fn huber_weight(r: f64, delta: f64) -> f64 {
    let a = r.abs();
    if a <= delta { 1.0 } else { delta / a }
}

/// Gauss–Newton step `−(JᵀJ)⁻¹ Jᵀr` restricted to the degrees of freedom `dofs` (indices into
/// (ω_x, ω_y, ω_z, t_x, t_y, t_z)), inverting only the eigen-directions whose eigenvalue is at least
/// `ratio` times the largest, so that directions the data cannot see get no update instead of an
/// arbitrary one driven by noise.
fn solve(
    jtj: &Matrix6<f64>,
    jtr: &Vector6<f64>,
    dofs: &[usize],
    ratio: f64,
) -> Option<Vector6<f64>> {
    let n = dofs.len();
    let a = nalgebra::DMatrix::from_fn(n, n, |i, j| jtj[(dofs[i], dofs[j])]);
    let b = nalgebra::DVector::from_fn(n, |i, _| jtr[dofs[i]]);
    let eig = a.symmetric_eigen();
    let largest = eig.eigenvalues.iter().fold(0.0f64, |m, v| m.max(*v));
    if !(largest.is_finite() && largest > 0.0) {
        return None;
    }
    let mut x = nalgebra::DVector::zeros(n);
    for (k, &lambda) in eig.eigenvalues.iter().enumerate() {
        if lambda > ratio * largest {
            let v = eig.eigenvectors.column(k);
            x -= v * (v.dot(&b) / lambda);
        }
    }
    let mut step = Vector6::zeros();
    for (i, &d) in dofs.iter().enumerate() {
        step[d] = x[i];
    }
    step.iter().all(|v| v.is_finite()).then_some(step)
}

fn quality(
    src: &[Vector3<f64>],
    last: &mut [u32],
    target: &Target,
    motion: &Isometry3<f64>,
    max_dist: f64,
) -> (f64, f64) {
    let max_sq = (max_dist * max_dist) as f32;
    let hits: Vec<Option<f32>> = src
        .par_iter()
        .zip(last.par_iter_mut())
        .with_min_len(CHUNK)
        .map(|(p, last)| {
            let ps = motion * Point3::from(*p);
            let q = [ps.x as f32, ps.y as f32, ps.z as f32];
            target
                .nearest_reusing(&q, last, max_sq)
                .and_then(|(_, d2)| (d2 <= max_sq).then_some(d2))
        })
        .collect();
    let inliers: Vec<f64> = hits.into_iter().flatten().map(f64::from).collect();
    if src.is_empty() || inliers.is_empty() {
        return (0.0, 0.0);
    }
    let fitness = inliers.len() as f64 / src.len() as f64;
    let rmse = (inliers.iter().sum::<f64>() / inliers.len() as f64).sqrt();
    (fitness, rmse)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reused_correspondences_are_the_exact_nearest_neighbours() {
        // Invariant: `nearest_reusing` returns the same target point as a fresh tree query, whatever
        // correspondence it remembered, so skipping queries cannot change the ICP's result.
        let points: Vec<Point3<f64>> = (0..900)
            .map(|i| {
                let (u, v) = (f64::from(i % 30), f64::from(i / 30));
                let wobble = (f64::from(i) * 0.731).sin() * 0.002;
                Point3::new(
                    u * 0.01 + wobble,
                    v * 0.008,
                    (u * 0.2).sin() * 0.02 + wobble,
                )
            })
            .collect();
        let intensity = vec![0.5; points.len()];
        let config = IcpConfig::default();
        let target = prepare_target(&points, &intensity, &Point3::origin(), &config);
        for j in 0..points.len() {
            target.local(j);
        }
        for k in 0..3000u32 {
            let f = f64::from(k);
            let q = [
                (0.15 + 0.16 * (f * 0.37).sin()) as f32,
                (0.12 + 0.13 * (f * 0.53).cos()) as f32,
                (0.02 * (f * 0.11).sin()) as f32,
            ];
            let fresh = target.tree.nearest(&q).expect("a non-empty tree");
            // Remember either the true nearest, a neighbour of it, or a far point.
            let mut last =
                [fresh.0 as u32, (fresh.0 as u32 + 1) % 900, (k * 7) % 900][k as usize % 3];
            let got = target.nearest_reusing(&q, &mut last, 1.0).expect("a hit");
            assert_eq!(got.0, fresh.0, "query {k}");
            assert!(
                (got.1 - fresh.1).abs() <= 1e-6 * fresh.1.max(1e-9),
                "query {k}"
            );
        }
    }

    #[test]
    fn closed_form_smallest_eigenvector_matches_the_iterative_solver() {
        // Invariant: the closed-form normal equals (up to sign) the iterative solver's.
        let pts = [
            Vector3::new(0.0, 0.0, 0.001),
            Vector3::new(0.1, 0.0, -0.002),
            Vector3::new(0.0, 0.1, 0.0),
            Vector3::new(0.1, 0.1, 0.003),
            Vector3::new(0.05, 0.02, 0.001),
            Vector3::new(0.02, 0.07, -0.001),
        ];
        let rot = UnitQuaternion::from_euler_angles(0.3, -0.2, 0.9);
        let mean: Vector3<f64> = pts.iter().map(|p| rot * p).sum::<Vector3<f64>>() / 6.0;
        let mut cov = Matrix3::zeros();
        for p in &pts {
            let d = rot * p - mean;
            cov += d * d.transpose();
        }
        let fast = smallest_eigenvector(&cov).expect("well-conditioned");
        let eig = cov.symmetric_eigen();
        let slow = eig.eigenvectors.column(eig.eigenvalues.imin()).into_owned();
        assert!(fast.dot(&slow).abs() > 1.0 - 1e-9, "{fast} vs {slow}");
        assert!(smallest_eigenvector(&Matrix3::identity()).is_none());
    }
}
