//! `safereach monitor` on a planar certificate: the same streaming readers, output and exit
//! codes as on the line ([`super::monitor`]), with samples checked by the library's
//! [`PlanarMonitor`] — text traces with the planar columns (`robot_y`, `obstacle_y`,
//! optionally `obstacle_vx`, `obstacle_vy`), or ROS 2 bags read in the plane. Trace obstacle
//! ids are matched to the certificate's obstacles by name.

use anyhow::{Context, Result};

use safereach::monitor::bag::BagItem;
use safereach::monitor::planar::PlanarMonitor;
use safereach::monitor::planar_region_certificate;
use safereach::monitor::trace::{Decoder, Ids};
use safereach::monitor::{Detail, Outcome, RobotSample, Sample, Summary, Verdict};
use safereach::proof::certificate_file::{CertificateFile, is_region_map};
use safereach::proof::json_read::from_json;
use safereach::proof::planar::certificate::PlanarCertificate;
use safereach::proof::region_map::RegionMap;

use super::exit::Exit;
use super::input::{self, Unreadable};
use super::monitor::{
    MonitorArgs, TraceMonitor, bag_options, is_bag, no_bag_flags, read_bag, read_text,
};
use super::output::Output;

/// The planar certificate `--certificate` holds, if it holds one.
pub fn planar_certificate(args: &MonitorArgs) -> Result<Option<PlanarCertificate>> {
    let path = &args.certificate;
    let text = input::certificate_text(path, Unreadable::CannotRead)?;
    if is_region_map(&text) {
        let map: RegionMap = from_json(&text)
            .with_context(|| format!("{}: not a safereach region map", path.display()))?;
        if map.planar.is_none() {
            return Ok(None);
        }
        anyhow::ensure!(
            args.at.is_empty(),
            "--at: a planar map is monitored at its box's weak corner (the certificate its \
             leaf carries), not at a named controller value"
        );
        let cert = planar_region_certificate(&map, args.leaf.as_deref())
            .with_context(|| format!("{}: certificate unusable", path.display()))?;
        return Ok(Some(cert));
    }
    match CertificateFile::from_json(&text) {
        Ok(CertificateFile::Planar(cert)) => {
            anyhow::ensure!(
                args.leaf.is_none() && args.at.is_empty(),
                "--leaf and --at choose a box of a region map; {} is a planar certificate",
                path.display()
            );
            Ok(Some(*cert))
        }
        // Any other kind, or an unreadable file, is the line monitor's to report.
        _ => Ok(None),
    }
}

/// Runs `safereach monitor` against the planar certificate `cert`: a ROS 2 bag read in the
/// plane (`BagOptions::plane`; `--lane-axis` places the problem's frame in the odometry
/// frame), or a text trace.
pub fn run(args: &MonitorArgs, cert: &PlanarCertificate, out: &mut Output) -> Result<Exit> {
    let monitor = || {
        PlanarMonitor::new(cert)
            .with_context(|| format!("{}: certificate unusable", args.certificate.display()))
    };
    if is_bag(args) {
        let mut options = bag_options(args)?;
        options.plane = true;
        return read_bag(args, &options, monitor()?, out);
    }
    no_bag_flags(args)?;
    read_text(args, monitor()?, out)
}

impl TraceMonitor for PlanarMonitor {
    fn verdict(&self) -> Verdict {
        PlanarMonitor::verdict(self)
    }
    fn sample(&mut self, decoder: &Decoder, s: &Sample) -> Outcome<'_> {
        self.observe_decoded(decoder, s)
    }
    fn robot(&mut self, decoder: &Decoder, r: &RobotSample) -> Outcome<'_> {
        self.observe_decoded_robot(decoder, r)
    }
    fn malformed(&mut self, t: Option<f64>, detail: Detail) -> Outcome<'_> {
        PlanarMonitor::malformed(self, t, detail)
    }
    fn item(&mut self, ids: &Ids, item: &BagItem) -> Outcome<'_> {
        self.observe_bag_item(ids, item)
    }
    fn summary(&self) -> (Summary, bool) {
        (PlanarMonitor::summary(self), self.checked_anything())
    }
}
