//! Parabola fits of tracked heights: the least-squares fit with its acceleration error, the
//! track's noise, and how many of the first frames follow one parabola.

use super::super::super::linalg::{Matrix, solve};
use super::{
    EXACT_TRACK_NOISE, MIN_FRAMES, NOISE_FRAMES, NOISY_START_FRAMES, PREDICTION_NOISE_FACTOR,
    PREDICTION_TOLERANCE, PREDICTION_TRACK_NOISE_FACTOR, RESIDUAL_NOISE_FACTOR, RESIDUAL_TOLERANCE,
};

/// How many of the first frames follow one parabola: the window grows frame by frame while
/// the parabola through the frames so far predicts the next one and still fits them all when
/// it is added, to within tolerances that grow with the track's noise ([`track_noise`]). An
/// exact track grows from three frames; a noisy one from [`NOISY_START_FRAMES`] or
/// [`MIN_FRAMES`], the first that one parabola fits (or from three when neither does, so a
/// motion that changes early reads as such). Below [`MIN_FRAMES`] it is too short to measure.
pub(super) fn clean_frames(times: &[f64], heights: &[f64]) -> usize {
    let count = times.len().min(heights.len());
    if count < 3 {
        return 0;
    }
    let noise = track_noise(&heights[..count]);
    let residual_tolerance = RESIDUAL_TOLERANCE.max(RESIDUAL_NOISE_FACTOR * noise);
    let fitting_start = |frames: usize| {
        let fit = fit_parabola(times.get(..frames)?, heights.get(..frames)?)?;
        (fit.residual <= residual_tolerance).then_some((frames, fit))
    };
    let noisy_start = if noise <= EXACT_TRACK_NOISE {
        None
    } else {
        [NOISY_START_FRAMES, MIN_FRAMES]
            .into_iter()
            .find_map(fitting_start)
    };
    let start = noisy_start.or_else(|| Some((3, fit_parabola(&times[..3], &heights[..3])?)));
    let Some((mut frames, mut fit)) = start else {
        return 0;
    };
    while frames < count {
        let tolerance = PREDICTION_TOLERANCE
            .max(PREDICTION_NOISE_FACTOR * fit.residual)
            .max(PREDICTION_TRACK_NOISE_FACTOR * noise);
        if (fit.at(times[frames]) - heights[frames]).abs() > tolerance {
            break;
        }
        match fit_parabola(&times[..=frames], &heights[..=frames]) {
            Some(next) if next.residual <= residual_tolerance => {
                fit = next;
                frames += 1;
            }
            _ => break,
        }
    }
    frames
}

/// The RMS noise of a track (m), from its second differences over the first
/// [`NOISE_FRAMES`] frames: white noise of σ gives differences of σ·√6. The spread is the RMS
/// deviation from the median difference with the largest tenth left out, so a contact or two do
/// not inflate it, scaled to be σ for white noise. A median absolute deviation would not do: a
/// track read from mask centroids moves in steps (most frames repeat the last height, then it
/// jumps by a fraction of a pixel), so most differences are zero and the median says the track
/// is exact while single frames sit ±1 step off any parabola.
fn track_noise(heights: &[f64]) -> f64 {
    let end = heights.len().min(NOISE_FRAMES);
    let mut differences: Vec<f64> = heights[..end]
        .windows(3)
        .map(|w| w[2] - 2.0 * w[1] + w[0])
        .collect();
    if differences.is_empty() {
        return 0.0;
    }
    differences.sort_by(f64::total_cmp);
    let centre = differences[differences.len() / 2];
    let mut deviations: Vec<f64> = differences.iter().map(|d| (d - centre).abs()).collect();
    deviations.sort_by(f64::total_cmp);
    let kept = deviations.len() - deviations.len() / 10;
    let mean_square = deviations[..kept].iter().map(|d| d * d).sum::<f64>() / kept as f64;
    mean_square.sqrt() / TRIMMED_NORMAL_RMS / 6.0_f64.sqrt()
}

/// The RMS of a standard normal variable with its largest tenth (in magnitude) left out:
/// √((0.9 − 2·1.6449·φ(1.6449)) / 0.9).
const TRIMMED_NORMAL_RMS: f64 = 0.789_3;

/// A least-squares parabola `h(t) = h₀ + v₀ τ + ½ a τ²`, `τ = t − t₀`.
pub(super) struct Parabola {
    start: f64,
    pub(super) height: f64,
    pub(super) velocity: f64,
    pub(super) acceleration: f64,
    pub(super) acceleration_error: f64,
    pub(super) residual: f64,
}

impl Parabola {
    fn at(&self, time: f64) -> f64 {
        let tau = time - self.start;
        self.height + self.velocity * tau + 0.5 * self.acceleration * tau * tau
    }
}

/// Fits a parabola to at least three samples over a positive time span (normal equations in
/// time scaled to [0, 1], heights taken from the first, so the 3×3 system stays well
/// conditioned); `None` otherwise or when the system is singular.
pub(super) fn fit_parabola(times: &[f64], heights: &[f64]) -> Option<Parabola> {
    let count = times.len().min(heights.len());
    if count < 3 {
        return None;
    }
    let start = times[0];
    let span = times[count - 1] - start;
    let base = heights[0];
    if !span.is_finite() || span <= 0.0 {
        return None;
    }
    let mut normal = Matrix::zeros(3);
    let mut rhs = [0.0; 3];
    for (t, h) in times.iter().zip(heights).take(count) {
        let s = (t - start) / span;
        let powers = [1.0, s, s * s];
        for row in 0..3 {
            for column in 0..3 {
                normal.add(row, column, powers[row] * powers[column]);
            }
            rhs[row] += powers[row] * (h - base);
        }
    }
    let coefficients = solve(&normal, &rhs)?;
    let squares: f64 = times
        .iter()
        .zip(heights)
        .take(count)
        .map(|(t, h)| {
            let s = (t - start) / span;
            let model = coefficients[0] + coefficients[1] * s + coefficients[2] * s * s;
            (h - base - model).powi(2)
        })
        .sum();
    let residual = (squares / count as f64).sqrt();
    // The acceleration's variance: σ² (XᵀX)⁻¹₂₂ with σ² = SSR / (n − 3), through a = 2 c₂ / T².
    let variance = if count > 3 {
        squares / (count - 3) as f64
    } else {
        0.0
    };
    let inverse_column = solve(&normal, &[0.0, 0.0, 1.0])?;
    let acceleration_error = 2.0 * (variance * inverse_column[2].max(0.0)).sqrt() / (span * span);
    let parabola = Parabola {
        start,
        height: base + coefficients[0],
        velocity: coefficients[1] / span,
        acceleration: 2.0 * coefficients[2] / (span * span),
        acceleration_error,
        residual,
    };
    [
        parabola.height,
        parabola.velocity,
        parabola.acceleration,
        parabola.acceleration_error,
        parabola.residual,
    ]
    .iter()
    .all(|v| v.is_finite())
    .then_some(parabola)
}
