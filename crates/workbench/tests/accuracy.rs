//! Every answer with its error bar: the estimate against what is known (Hertz's solution), the
//! flags against the accuracy asked, and what an answer says where no coarser grid can answer.

use ehl_workbench::{Outcome, accuracy, output};

#[test]
fn the_dry_contact_s_estimated_errors_bracket_its_actual_error_against_hertz() {
    // The dry contact on 65²: its maximum pressure and contact extents against Hertz's p_h and
    // 2a. Each estimate (three grids, 65², 33², 17²) must be at least the actual error, and
    // small where the answer is good: the peak pressure is within 1e-4 of p_h on 65² (its
    // estimate, 8e-4, reads the peak's node-to-node wobble between grids), the extent within
    // 1.4 % (its estimate within ten times that: an estimate that says nothing is as wrong as
    // one that misses).
    let scene = ehl_scene::builtin("hertz").unwrap().with_points(65).unwrap();
    let c = accuracy::run(&scene, true).unwrap();
    let e = c.estimate.as_ref().unwrap();
    assert_eq!(e.grids, [65, 33, 17]);
    let ob = c.observables();
    let s = c.scales();
    let actual = [
        (ob.max_pressure_pa / s.p_h - 1.0).abs(),
        (ob.contact_extent_x_m / (2.0 * s.a) - 1.0).abs(),
    ];
    for (k, act, most) in [(2, actual[0], 2e-3), (3, actual[1], 10.0 * actual[1])] {
        let est = e.errors[k].unwrap().relative;
        let name = ehl_workbench::accuracy::OBSERVED[k].0;
        assert!(est >= act && est < most, "{name}: estimated {est:.2e}, actual {act:.2e}");
    }
    // The dry contact has no film: no film error, and nothing flagged at the default 5 %.
    assert!(e.errors[0].is_none() && e.errors[1].is_none());
    assert!(c.flags.is_empty(), "{:?}", c.flags);
    // The writer's summary carries the block: each observable with its error, the grids.
    let v = output::summary(&c);
    let a = &v["accuracy"];
    assert_eq!(a["estimated"], true);
    assert_eq!(a["grids"], serde_json::json!([65, 33, 17]));
    assert!(a["observables"]["p_max"]["error"].as_f64().unwrap() > 0.0);
    assert!(a["observables"]["h_c"]["error"].is_null());
}

#[test]
fn an_error_beyond_the_accuracy_asked_is_flagged_with_the_grid_that_would_meet_it() {
    // The textbook contact (M = 20, L = 10: a thick film) on 129², its coarser grids 65² and
    // 33² answering: its films are a percent or two off there. Asked for 0.1 %, it is flagged,
    // naming a finer grid; asked for 50 %, it is not.
    let base = ehl_scene::builtin("reynolds-m20-l10").unwrap().with_points(129).unwrap();
    let tight = accuracy::Checked::new(
        &base,
        ehl_workbench::run_scene(&base).unwrap(),
        accuracy::Checking { estimate: true, limit: 1e-3 },
    );
    let f = tight.flags.join("; ");
    assert!(f.contains("h_c ±") && f.contains("would meet it"), "{f}");
    assert!(tight.caveat().unwrap().contains("would meet it"));
    let e = tight.estimate.as_ref().unwrap();
    assert!(e.errors[0].unwrap().order.is_some(), "three grids answer for a thick film: {e:?}");
    let loose = accuracy::Checked::new(
        &base,
        ehl_workbench::run_scene(&base).unwrap(),
        accuracy::Checking { estimate: true, limit: 0.5 },
    );
    assert!(loose.flags.is_empty(), "{:?}", loose.flags);
    // Asked not to estimate: said, as a flag.
    let none = accuracy::Checked::new(
        &base,
        ehl_workbench::run_scene(&base).unwrap(),
        accuracy::Checking { estimate: false, limit: 0.05 },
    );
    assert!(none.flags[0].contains("not estimated"));
}

#[test]
fn where_no_coarser_grid_can_hold_the_film_the_solver_s_grid_law_gives_the_error() {
    // The seed's contact fed 25 nm on 129²: 65² is beyond where its film can exist (not run),
    // and 129² is on the edge. The films' error comes from the solver's measured law, stated,
    // and is beyond 5 %: flagged. (The flooded film on 129² is 9.75 nm against 12.3 nm
    // converged: 21 % off; the law says 1.25 · 4.3 ρ² / 3 at ρ = 0.5: 45 %.)
    let seed = ehl_scene::builtin("seed").unwrap().with_points(129).unwrap();
    let one = seed.for_model(ehl_scene::Model::Reynolds);
    let c = accuracy::run(&one, true).unwrap();
    let e = c.estimate.as_ref().unwrap();
    assert!(e.method.contains("measured grid law"), "{}", e.method);
    let hc = e.errors[0].unwrap().relative;
    assert!((0.21..1.0).contains(&hc), "{hc}");
    assert!(c.flags.iter().any(|f| f.starts_with("h_c ±")), "{:?}", c.flags);
}

/// The cycles a Reynolds outcome's steady solve took.
fn cycles(o: &dyn Outcome) -> usize {
    let r = o.as_any().downcast_ref::<ehl_workbench::reynolds::ReynoldsOutcome>();
    r.unwrap().report.cycles
}

#[test]
fn a_coarser_grid_started_from_the_finer_answer_reaches_its_own_answer_in_fewer_cycles() {
    // Two answers and their half grids, each solved for the estimate from the finer answer
    // and, as any scene, from Hertz: the seed's contact fed 25 nm (mass conserving) on 257²
    // and 129², the textbook contact flooded (M = 20, L = 10) on 129² and 65². The start must
    // not change the coarse answer: both stop with the film settled (the estimate's grid within
    // 5e-4 a cycle, the scene's within 1e-4), so their central films agree within a tenth of
    // what the two grids differ by (15 % and 1 %); a start that kept the finer film would miss
    // by all of it.
    for (name, model, n) in [
        ("seed", ehl_scene::Model::Reynolds, 257),
        ("reynolds-m20-l10", ehl_scene::Model::Reynolds, 129),
    ] {
        let fine = ehl_scene::builtin(name).unwrap().for_model(model).with_points(n).unwrap();
        let answer = ehl_workbench::run_scene(&fine).unwrap();
        let coarse = fine.with_points(n / 2 + 1).unwrap();
        let m = ehl_workbench::run::model(model).unwrap();
        let warm =
            ehl_workbench::run::run_coarser(&m.for_estimate(coarse.clone()), answer.as_ref())
                .unwrap();
        let cold = ehl_workbench::run_scene(&coarse).unwrap();
        let film = |o: &dyn Outcome| o.observables().central_film_m;
        let (hf, hw, hc) = (film(answer.as_ref()), film(warm.as_ref()), film(cold.as_ref()));
        assert!(
            (hw - hc).abs() < 0.1 * (hf - hc).abs(),
            "{name}: from the finer answer {hw:e}, from its own start {hc:e}, finer {hf:e}"
        );
        let (cw, cc) = (cycles(warm.as_ref()), cycles(cold.as_ref()));
        assert!(cw < cc, "{name}: {cw} cycles from the finer answer, {cc} from its own start");
    }
}

#[test]
fn a_domain_check_started_from_the_answer_reaches_the_grown_domain_s_own_answer() {
    // A sweep's domain check (the half grid's cells, the inlet 1.5× as long, `y` grown alike)
    // starts from the point's answer where that has points, and where it has none from no
    // pressure and the supply as it arrives. The seed's contact on 257² over its ±1.25 a, its
    // inlet short of the flooded film's starvation boundary: flooded, the grown inlet thickens
    // the film by a few per cent, and the check started from the answer must find that change,
    // agreeing with the grown domain solved from Hertz within a tenth of it (a start that kept
    // the short inlet's film would miss by all of it); fed 25 nm, the meniscus stands inside
    // the short inlet and the grown one changes nothing: the two agree within 1e-3 (each
    // stops on a change below 5e-4 a cycle, its remaining error about as much). Either way
    // in fewer cycles than from Hertz.
    for model in [ehl_scene::Model::ReynoldsFlooded, ehl_scene::Model::Reynolds] {
        let fine = ehl_scene::builtin("seed").unwrap().for_model(model).with_points(257).unwrap();
        let answer = ehl_workbench::run_scene(&fine).unwrap();
        let grown = accuracy::rule::domain_check(&fine);
        let half = ehl_workbench::run_scene(&accuracy::rule::grid_check(&fine)).unwrap();
        let warm = accuracy::run_check(&grown, answer.as_ref()).unwrap();
        let cold = ehl_workbench::run_scene(&grown).unwrap();
        let film = |o: &dyn Outcome| o.observables().central_film_m;
        let (hh, hw, hc) = (film(half.as_ref()), film(warm.as_ref()), film(cold.as_ref()));
        let bound = match model {
            ehl_scene::Model::ReynoldsFlooded => {
                assert!(hc / hh - 1.0 > 0.01, "the grown inlet's film {hc:e} against {hh:e}");
                0.1 * (hc - hh).abs()
            }
            _ => 1e-3 * hc,
        };
        assert!(
            (hw - hc).abs() < bound,
            "{model:?}: from the answer {hw:e}, from Hertz {hc:e}, the short inlet's {hh:e}"
        );
        let (cw, cc) = (cycles(warm.as_ref()), cycles(cold.as_ref()));
        assert!(cw < cc, "{model:?}: {cw} cycles from the answer, {cc} from Hertz");
    }
}

#[test]
fn a_closed_film_from_the_dry_contact_is_known_to_what_its_grid_resolves() {
    // The seed's Reynolds case at 1e-6 m/s on 65²: its film (0.05 nm) is thinner than the
    // grid's dry gap error at the contact's edge, and the answer is the closed film, from the
    // dry contact. Its films' error is that gap error (0.5 × cell² in a²/R: 1.45 nm), not the
    // grid law's thousands of nm, nor the zero change of coarser grids that close as well.
    let mut scene = ehl_scene::builtin("reynolds-seed").unwrap().with_points(65).unwrap();
    scene.conditions.rolling_velocity_m_s = Some(1e-6);
    scene.outputs.figures = false;
    let c = accuracy::run(&scene, true).unwrap();
    let e = c.estimate.as_ref().unwrap();
    let cell = scene.grid().dx();
    let gap = c.scales().h_si(ehl_reynolds::formulas::DRY_GAP_ERROR_PER_CELL2 * cell * cell);
    for k in [0, 1] {
        let bar = e.errors[k].unwrap();
        assert!((bar.absolute / gap - 1.0).abs() < 1e-12, "{bar:?} against {gap:e} m");
    }
    assert!(e.method.contains("closed film"), "{}", e.method);
}

#[test]
fn an_answer_whose_contact_swallowed_the_oil_says_how_much_and_is_flagged() {
    // The seed's Reynolds case fed 0.2 nm on 65²: the grid's dry gap error at the contact's
    // edge (1.1 nm) is five times the film the oil makes, the answer is dry, and the touching
    // points take 81 % of the supply (measured), oil the equations destroy. The answer says
    // so, in its summary and as a caveat that flags it; on 129² (−0.37 %, within the oil
    // tolerance of 1 %) it does not.
    let scene = |n: usize| {
        let s = ehl_scene::builtin("reynolds-seed").unwrap().with_points(n).unwrap();
        let mut json: serde_json::Value = serde_json::from_str(&s.to_json()).unwrap();
        json["supply"] = serde_json::json!({ "thickness_m": 0.2e-9 });
        json["outputs"]["figures"] = false.into();
        ehl_scene::Scene::from_json(&json.to_string(), "the test").unwrap()
    };
    let coarse = ehl_workbench::run_scene(&scene(65)).unwrap();
    let oil = &output::summary(coarse.as_ref())["details"]["supply"]["oil"];
    let taken = oil["into_contact"].as_f64().unwrap();
    assert!((0.5..1.0).contains(&taken), "{oil}");
    // Where the oil went adds up to the supply (what the equations leave unmet is 1e-5 of it).
    let parts = ["carried_out", "pressed_out_at_edges", "into_contact", "stored", "unaccounted"];
    let sum: f64 = parts.iter().map(|k| oil[*k].as_f64().unwrap()).sum();
    assert!((sum - 1.0).abs() < 1e-9, "{oil}");
    let caveat = coarse.caveat().unwrap_or_default();
    assert!(caveat.contains("of the supplied oil where they touch"), "{caveat}");
    let fine = ehl_workbench::run_scene(&scene(129)).unwrap();
    assert!(fine.caveat().is_none_or(|c| !c.contains("supplied oil")), "{:?}", fine.caveat());
}
