//! The right-hand side and the stepping loop do not allocate: counted with a global
//! allocator wrapper, per thread, so that the test harness's own threads (its main thread
//! sets up its first blocking receive while the test runs, which a loaded CI machine once
//! timed into the counted window: 4 allocations) cannot count against the engine.

use bearing_core::dynamics::rhs::{rhs, Diagnostics};
use bearing_core::model::Model;
use bearing_core::quasi_static::{initial_state, solve_model};
use bearing_core::scene::{fault_case_scene, FaultCase, Fidelity, Integrator};
use bearing_core::simulation::{simulate, RunControl};
use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;

struct Counting;

thread_local! {
    // const-initialised and without a destructor: reading it never allocates
    static ALLOCS: Cell<usize> = const { Cell::new(0) };
}

/// Allocations made so far by the calling thread.
fn allocations() -> usize {
    ALLOCS.with(|a| a.get())
}

fn count_one() {
    // try_with: a thread being torn down has no slot left, and is not the test's
    let _ = ALLOCS.try_with(|a| a.set(a.get() + 1));
}

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, l: Layout) -> *mut u8 {
        count_one();
        unsafe { System.alloc(l) }
    }
    unsafe fn dealloc(&self, p: *mut u8, l: Layout) {
        unsafe { System.dealloc(p, l) }
    }
    unsafe fn realloc(&self, p: *mut u8, l: Layout, n: usize) -> *mut u8 {
        count_one();
        unsafe { System.realloc(p, l, n) }
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;

// One test function, so that nothing else of this binary runs on its thread.
#[test]
fn rhs_and_stepping_loop_do_not_allocate() {
    // every fidelity level: the reduced ones solve a Newton balance per ball inside the
    // right-hand side and rewrite slots after each step (`BearingSystem::project`)
    for fidelity in [
        Fidelity::Full,
        Fidelity::QuasiStaticBalls,
        Fidelity::ConcentricCage,
    ] {
        let mut scene = fault_case_scene("h7005c", FaultCase::Compound).unwrap();
        scene.solver.fidelity = fidelity;
        no_allocation(&scene, fidelity);
    }
    // and the Rosenbrock method at a reduced level, whose Jacobian is the cage's land film
    // alone, filled afresh at every step from a scratch state
    let mut scene = fault_case_scene("h7005c", FaultCase::Compound).unwrap();
    scene.solver.fidelity = Fidelity::QuasiStaticBalls;
    scene.solver.integrator = Integrator::RosenbrockW;
    no_allocation(&scene, Fidelity::QuasiStaticBalls);
}

fn no_allocation(scene: &bearing_core::scene::Scene, fidelity: Fidelity) {
    let m = Model::new(&scene.validated().unwrap());
    let qs = solve_model(&m, m.shaft_speed(0.0)).unwrap();
    let y = initial_state(&m, &qs);
    let mut dy = vec![0.0; y.len()];
    let mut diag = Diagnostics::new(m.z);
    let before = allocations();
    for k in 0..100 {
        rhs(&m, k as f64 * 1e-6, &y, &mut dy, Some(&mut diag));
    }
    assert_eq!(allocations() - before, 0, "{fidelity:?}: rhs allocated");

    // A run allocates its buffers up front and its result at the end; the number of
    // allocations must not depend on how many steps it takes.
    let count = |duration: f64| {
        let mut s = scene.clone();
        s.solver.duration = duration;
        s.solver.sample_rate = 1000.0; // same sample count (3) for both durations
        let before = allocations();
        let r = simulate(&s.validated().unwrap(), RunControl::default()).unwrap();
        (allocations() - before, r.summary.stats.accepted_steps)
    };
    let (a1, s1) = count(0.0025);
    let (a2, s2) = count(0.0029);
    assert!(
        s2 > s1 + 10,
        "{fidelity:?}: the second run must take more steps ({s1} vs {s2})"
    );
    assert_eq!(
        a1, a2,
        "{fidelity:?}: allocations grew with the step count: {a1} vs {a2}"
    );
}
