//! Rolling kinematics of a ball between two races.

use nalgebra::{Matrix3, Vector3};

/// Ball orbital speed and angular velocity for rolling without slip at both contact
/// centres and no spin about the outer contact normal (outer-race control), for a ball
/// centre at radius `r` (m), contact angles `alpha_i`, `alpha_o` (rad), ball radius `rb`
/// (m) and inner-ring speed `w_inner` (rad/s, outer ring fixed).
/// Returns `[orbital speed, w_x, w_r]`, rad/s.
pub fn rolling_kinematics(r: f64, alpha_i: f64, alpha_o: f64, rb: f64, w_inner: f64) -> [f64; 3] {
    let (pix, pir) = (-rb * alpha_i.sin(), -rb * alpha_i.cos());
    let (pox, por) = (rb * alpha_o.sin(), rb * alpha_o.cos());
    // unknowns (thd, wx, wr): tangential surface speeds match the races
    let a = Matrix3::new(
        r,
        pir,
        -pix,
        r,
        por,
        -pox,
        0.0,
        alpha_o.sin(),
        alpha_o.cos(),
    );
    let b = Vector3::new(w_inner * (r + pir), 0.0, 0.0);
    let x = a.lu().solve(&b).unwrap_or_else(Vector3::zeros);
    [x[0], x[1], x[2]]
}
