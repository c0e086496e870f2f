//! The surfaces' relief through both models: a wave rolled through the seed's contact until
//! its passage repeats, each model's last passage against what must hold whatever the model
//! (a flat wave is the steady answer; the wave the films carry is proportional to the wave
//! the surfaces carry) and against the amplitude reduction's published limit.

use ehl_scene::Model;
use ehl_workbench::compare::{self, Comparison};

/// `waviness-compare` with its wave's amplitude set to `amplitude_m` [m], run without figures
/// with each answer's error estimated (as `ehl compare` runs it), every model converged.
fn wave(amplitude_m: f64) -> Comparison {
    let mut scene = ehl_scene::builtin("waviness-compare").unwrap();
    scene.outputs.figures = false;
    let Some(ehl_scene::Feature::Waviness(w)) = scene.run.as_mut().map(|r| &mut r.features[0])
    else {
        panic!("a wavy scene")
    };
    w.amplitude_m = amplitude_m;
    let c = compare::run_checked(&scene, compare::Schedule::one_at_a_time(false), true);
    assert!(c.all_converged(), "{}", c.table());
    c
}

fn passage(c: &Comparison, m: Model) -> ehl_core::Passage {
    let e = c.entries.iter().find(|e| e.model == m).unwrap();
    e.outcome.as_ref().unwrap().passage().expect("a march through a wave has a passage")
}

#[test]
fn a_flat_wave_rolls_on_the_steady_answer_and_stops_periodic_in_both_models() {
    let c = wave(0.0);
    for e in &c.entries {
        let o = e.outcome.as_ref().unwrap();
        let h = o.history().unwrap();
        let (start, end) = (h[0].1.central_film_m, h.last().unwrap().1.central_film_m);
        // Each step re-solves a state that is already the answer: what moves is the solvers'
        // own tolerance (films to 1e-4 of their scale per step, the layer's contact to 1e-7).
        assert!((end / start - 1.0).abs() < 1e-3, "{:?}: {start} → {end}", e.model);
        let s = ehl_workbench::output::summary(o.as_ref()).to_string();
        assert!(s.contains("periodic: largest change"), "{:?} did not stop periodic", e.model);
        let p = passage(&c, e.model);
        assert_eq!(p.lambda, None, "a flat wave has no RMS height: no λ");
        // The fit's floor: a film with no wave in it gives 1e-5 nm of one (the quartic trend
        // takes the film's own shape).
        assert!(p.amplitude_ratio.is_none() && p.deformed_amplitude_m.unwrap() < 1e-12);
    }
}

#[test]
fn a_wave_through_the_seed_contact_is_flattened_by_the_reynolds_film_in_proportion() {
    let (full, half) = (wave(5e-9), wave(2.5e-9));
    let (r, r_half) = (passage(&full, Model::Reynolds), passage(&half, Model::Reynolds));
    // The seed's contact is a heavily loaded one (Moes M = 2223, L = 2.49): a wave of a/4 is
    // long against it, the amplitude reduction's parameter ∇ = (λ/a) M^(3/4) / L^(1/2) = 51
    // (reference/amplitude-reduction.json) puts A_d/A_i at its long-wave limit, 0: below
    // 0.05 (a twentieth of the wave left; the fit's own floor on a flat wave is 1e-5 nm).
    let ratio = r.amplitude_ratio.unwrap();
    assert!(ratio < 0.05, "Reynolds A_d/A_i = {ratio}");
    // The films carry the wave in proportion to the surfaces' (the small-amplitude limit):
    // halving A_i halves A_d, to 10 % here, where what is left of the wave (0.04 nm) is of
    // the order of the film's step-to-step error and its phase against the grid at the end.
    let lin = r_half.deformed_amplitude_m.unwrap() / r.deformed_amplitude_m.unwrap();
    assert!((lin - 0.5).abs() < 0.05, "Reynolds A_d(A_i/2) / A_d(A_i) = {lin}");
    // The layer model keeps much of the wave: its layer is compressed where the wave's crest
    // passes, it cannot flow around it.
    let l = passage(&full, Model::Layer);
    let l_half = passage(&half, Model::Layer);
    let (lr, lr_half) = (l.amplitude_ratio.unwrap(), l_half.amplitude_ratio.unwrap());
    // (measured on 129²: 0.47 of a 5 nm wave, 0.40 of a 2.5 nm one: not proportional, the
    // layer's stiffness rises as it is compressed).
    assert!(lr > 10.0 * ratio, "layer A_d/A_i = {lr}, Reynolds {ratio}");
    assert!(lr_half < lr, "layer A_d/A_i: {lr_half} at A_i/2, {lr} at A_i");
    // The layer's error estimate leaves out the quarter grid (33²), which would carry the wave
    // on 3.2 cells: an answer for another surface.
    let layer = full.entries.iter().find(|e| e.model == Model::Layer).unwrap();
    let (est, _) = layer.outcome.as_ref().unwrap().estimate().unwrap();
    assert_eq!(est.grids, vec![129, 65], "{}", est.method);
    // λ of the run: the passage's mean central film over the wave's RMS height A/√2.
    let rms = 5e-9 / 2f64.sqrt();
    assert!((r.lambda.unwrap() - r.central_film_mean_m / rms).abs() < 1e-12);
}

#[test]
fn a_rough_surface_rolls_through_the_layer_model_and_reports_its_last_transit() {
    // The layer model alone on 65² (the correlation length on 3.8 cells): a random surface
    // never repeats, so the run ends at its time limit and its passage is the last transit of
    // the domain, 2.5 a.
    let scene = ehl_scene::builtin("roughness-compare").unwrap().for_model(Model::Layer);
    let mut scene = scene.with_points(65).unwrap();
    scene.outputs.figures = false;
    let o = ehl_workbench::run_scene(&scene).unwrap();
    let p = o.passage().expect("a march through a rough surface has a passage");
    let a = o.scales().a;
    assert!((p.travel_m / (2.5 * a) - 1.0).abs() < 1e-12, "{} m", p.travel_m);
    // One step a cell: the transit's 64 steps, its first instant left out.
    assert_eq!(p.records, 64);
    assert!((p.lambda.unwrap() - p.central_film_mean_m / 3e-9).abs() < 1e-12);
    assert!(
        p.central_film_min_m < p.central_film_mean_m
            && p.central_film_mean_m < p.central_film_max_m
    );
    assert_eq!(p.amplitude_ratio, None, "a random surface has no single wave");
    let s = ehl_workbench::output::summary(o.as_ref()).to_string();
    // Ended by its time limit (`max_time_s` is in every summary's settings: the stop reason).
    assert!(s.contains("not finished by the time limit"), "{s}");
}

#[test]
fn a_rough_patch_rolls_in_and_the_layer_model_reports_the_load_its_solids_carry() {
    // roughness-mixed-compare's layer side on 65² (the correlation length doubled to 20 µm to
    // sit on 3.8 cells): the 200 nm layer pressed into 20 nm roughness leaves no layer on some
    // crests, and the solids there carry a share of the load; with the roughness at 0 no crest
    // does. The passage's mean is the records' mean of the same share (the monitor's column),
    // over the last transit's 128 steps (two a cell).
    let run = |rq: f64| {
        let mut scene =
            ehl_scene::builtin("roughness-mixed-compare").unwrap().for_model(Model::Layer);
        scene.outputs.figures = false;
        if let Some(ehl_scene::Feature::Roughness(r)) =
            scene.run.as_mut().map(|r| &mut r.features[0])
        {
            r.correlation_length_m = 2e-5;
            r.rq_m = rq;
        }
        ehl_workbench::run_scene(&scene.with_points(65).unwrap()).unwrap()
    };
    let o = run(2e-8);
    let p = o.passage().expect("a march through a rough surface has a passage");
    assert_eq!(p.records, 128);
    let (mean, max) = (p.contact_load_share_mean.unwrap(), p.contact_load_share_max.unwrap());
    assert!(mean > 0.0 && max >= mean && max < 1.0, "{p:?}");
    assert!(p.contact_area_mean_m2.unwrap() > 0.0);
    let shares = o.contact_history().unwrap();
    let last: Vec<f64> = shares.iter().rev().take(128).map(|c| c.0).collect();
    let records_mean = last.iter().sum::<f64>() / 128.0;
    assert!((mean - records_mean).abs() < 1e-15, "{mean} against {records_mean}");
    // Smooth: a layer everywhere, nothing touches (exactly 0: the mask is empty).
    let p = run(0.0).passage().expect("a roughness of 0 still has its passage");
    assert_eq!(p.contact_load_share_max, Some(0.0), "{p:?}");
}
