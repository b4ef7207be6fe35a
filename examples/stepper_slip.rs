//! docs/motors_slip.svg: a stepper slipping, seen at its shaft. The Faze4's wave at
//! `--freq 12.566` with `--motors faze4 --drive stepper` (the open-loop drive of
//! docs/motors.md), every step recorded; around the slip of the joint that lost the fewest
//! full steps, the angle the driver holds
//! (its microstep) and the rotor's angle, and below, the rotor's offset from it in full steps:
//! it swings past the torque–angle curve's peak (1 full step) and its unstable top (2), and
//! settles about the next stable point, 4 full steps (one electrical cycle) off.
//!
//!     cargo run --release --example stepper_slip [-- docs/motors_slip.svg | F.png]

use plotters::coord::Shift;
use plotters::prelude::*;

use faze4::control::OpenLoopStepper;
use faze4::faze4::motors::faze4 as faze4_motors;
use faze4::sim::{Drive, Recorder, Sample, Scenario, StopFlag, run};
use faze4::traj::{Trajectory, Wave};

/// Time shown before and after the first slip (s).
const BEFORE: f64 = 0.012;
const AFTER: f64 = 0.030;
const FONT: &[u8] = include_bytes!("../assets/fonts/DejaVuSans.ttf");

/// Every step's joint angles and commands.
struct Capture {
    dt: f64,
    rows: Vec<(f64, Vec<f64>, Vec<f64>)>,
}

impl Recorder for Capture {
    fn period(&self) -> f64 {
        self.dt
    }

    fn record(&mut self, s: &Sample) -> faze4::Result<()> {
        self.rows.push((s.t, s.q.to_vec(), s.q_cmd.to_vec()));
        Ok(())
    }
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let out = std::env::args().nth(1).unwrap_or_else(|| "docs/motors_slip.svg".into());
    let mut model = faze4::faze4::model();
    let motors = faze4::config::motors::fit(&mut model, Some(faze4_motors(None)), &[], &[])?;
    let n = model.dof();
    let wave = Trajectory::Wave(Wave {
        amplitude: vec![25f64.to_radians(); n],
        omega: 12.566,
        center: vec![0.0; n],
    });
    let scenario = Scenario::builder(model, wave)
        .command("wave --freq 12.566")
        .collisions(None)
        .duration(0.5)
        .motors(motors.unwrap_or_default())
        .drive(Drive::Stepper(Default::default()))
        .build()?;
    let mut capture = Capture {
        dt: scenario.dt,
        rows: Vec::new(),
    };
    let summary = run(&scenario, &mut [&mut capture], &StopFlag::new())?;
    println!("{}", summary.verdict);
    let motors = summary.motors.as_deref().unwrap_or(&[]);
    // the cleanest slip: the joint that lost the fewest full steps (then the earliest)
    let (joint, t_slip, _) = (motors.iter().enumerate())
        .filter_map(|(i, m)| {
            let m = m.as_ref()?;
            Some((i, m.loses_steps_at.flatten()?, m.steps_lost.filter(|&n| n > 0)?))
        })
        .min_by(|a, b| a.2.cmp(&b.2).then(a.1.total_cmp(&b.1)))
        .ok_or("no joint slipped")?;
    let drive: OpenLoopStepper = *scenario.drives[joint].stepper().ok_or("no drive")?;
    let ratio = scenario.model.joints[joint].gear_ratio;
    let full = drive.full_step();
    let (t0, t1) = ((t_slip - BEFORE).max(0.0), t_slip + AFTER);
    let rows: Vec<Row> = (capture.rows.iter())
        .filter(|(t, ..)| (t0..=t1).contains(t))
        .map(|(t, q, q_cmd)| {
            let held = drive.commanded(ratio * q_cmd[joint]);
            let rotor = ratio * q[joint];
            Row {
                ms: *t * 1e3,
                held: held.to_degrees(),
                rotor: rotor.to_degrees(),
                lag: (rotor - held) / full,
            }
        })
        .collect();

    plotters::style::register_font("sans-serif", FontStyle::Normal, FONT).map_err(|_| "font")?;
    let size = (1000, 720);
    let title = format!(
        "faze4 · J{} ({}) under --motors faze4 --drive stepper, wave --freq 12.566: a slip at t = {:.1} ms",
        joint + 1,
        scenario.model.joints[joint].name,
        t_slip * 1e3
    );
    let figure = Figure {
        title,
        rows,
        drive,
        t: (t0, t1),
    };
    if out.ends_with(".png") {
        let mut rgb = vec![0u8; (size.0 * size.1 * 3) as usize];
        figure.draw(BitMapBackend::with_buffer(&mut rgb, size).into_drawing_area())?;
        let mut encoder = png::Encoder::new(std::fs::File::create(&out)?, size.0, size.1);
        encoder.set_color(png::ColorType::Rgb);
        encoder.write_header()?.write_image_data(&rgb)?;
    } else {
        figure.draw(SVGBackend::new(&out, size).into_drawing_area())?;
    }
    println!("{out}: J{} slips at t = {t_slip:.4} s", joint + 1);
    Ok(())
}

/// One recorded step: t (ms), the driver's and the rotor's angle (° at the shaft), the rotor's
/// offset from the driver's (full steps).
struct Row {
    ms: f64,
    held: f64,
    rotor: f64,
    lag: f64,
}

/// The figure: the rows over `t` (s).
struct Figure {
    title: String,
    rows: Vec<Row>,
    drive: OpenLoopStepper,
    t: (f64, f64),
}

impl Figure {
    fn draw<DB: DrawingBackend>(&self, root: DrawingArea<DB, Shift>) -> Result<(), Box<dyn std::error::Error>>
    where
        DB::ErrorType: 'static,
    {
        let Figure {
            title,
            rows,
            drive,
            t: (t0, t1),
        } = self;
        let (t0, t1) = (*t0, *t1);
        root.fill(&WHITE)?;
        let (top, body) = root.split_vertically(40);
        top.draw(&Text::new(title.as_str(), (16, 12), ("sans-serif", 17).into_font()))?;
        let (upper, lower) = body.split_vertically(380);
        let x = (t0 * 1e3)..(t1 * 1e3);
        let span = |f: &dyn Fn(&Row) -> f64| {
            let (lo, hi) = rows
                .iter()
                .map(f)
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), v| (l.min(v), h.max(v)));
            let pad = 0.06 * (hi - lo).max(1e-9);
            (lo - pad)..(hi + pad)
        };
        let y = {
            let a = span(&|r| r.held);
            let b = span(&|r| r.rotor);
            a.start.min(b.start)..a.end.max(b.end)
        };
        let mut chart = ChartBuilder::on(&upper)
            .margin(10)
            .x_label_area_size(40)
            .y_label_area_size(70)
            .build_cartesian_2d(x.clone(), y)?;
        chart
            .configure_mesh()
            .x_desc("t (ms)")
            .y_desc("motor angle (° at the shaft)")
            .label_style(("sans-serif", 13))
            .draw()?;
        let held = RGBColor(31, 119, 180);
        let rotor = RGBColor(214, 39, 40);
        chart
            .draw_series(LineSeries::new(
                rows.iter().map(|r| (r.ms, r.held)),
                held.stroke_width(2),
            ))?
            .label(format!(
                "commanded: the microstep the driver holds (1/{} step)",
                drive.microsteps
            ))
            .legend(move |(x, y)| PathElement::new([(x, y), (x + 18, y)], held.stroke_width(2)));
        chart
            .draw_series(LineSeries::new(
                rows.iter().map(|r| (r.ms, r.rotor)),
                rotor.stroke_width(2),
            ))?
            .label("actual: the rotor")
            .legend(move |(x, y)| PathElement::new([(x, y), (x + 18, y)], rotor.stroke_width(2)));
        chart
            .configure_series_labels()
            .position(SeriesLabelPosition::LowerLeft)
            .background_style(WHITE.mix(0.85))
            .border_style(RGBColor(200, 200, 200))
            .label_font(("sans-serif", 13))
            .draw()?;

        let mut lag = ChartBuilder::on(&lower)
            .margin(10)
            .x_label_area_size(40)
            .y_label_area_size(70)
            .build_cartesian_2d(x, span(&|r| r.lag).start.min(-1.5)..span(&|r| r.lag).end.max(1.5))?;
        lag.configure_mesh()
            .x_desc("t (ms)")
            .y_desc("rotor − commanded (full steps)")
            .label_style(("sans-serif", 13))
            .draw()?;
        for (level, what) in [
            (0.0, "stable"),
            (-1.0, "peak"),
            (-2.0, "unstable"),
            (-4.0, "stable, 1 cycle off"),
            (1.0, "peak"),
        ] {
            let style = if what.starts_with("stable") {
                BLACK.mix(0.6)
            } else {
                BLACK.mix(0.25)
            };
            lag.draw_series(LineSeries::new(
                [(t0 * 1e3, level), (t1 * 1e3, level)],
                style.stroke_width(1),
            ))?;
            lag.draw_series([Text::new(
                what,
                (t1 * 1e3 - 0.18 * (t1 - t0) * 1e3, level + 0.1),
                ("sans-serif", 12),
            )])?;
        }
        lag.draw_series(LineSeries::new(
            rows.iter().map(|r| (r.ms, r.lag)),
            rotor.stroke_width(2),
        ))?;
        root.present()?;
        Ok(())
    }
}
