//! The structure of a LiDAR scan: each point lies on a scan line, one beam (ring) of a
//! spinning sensor or one row of a terrestrial scanner's angular grid, seen from one station.
//!
//! Along a line, returns lie a few centimetres apart; between lines the gap grows with range
//! to metres. The nearest neighbours of a point are then all on its own line, so `prep`
//! builds scan-aware neighbourhoods from the lines instead (`scan::neighborhood`).

use std::collections::HashMap;

use glam::{DVec3, Vec3};

use crate::scan::noise::range_noise;

/// More distinct sensor positions than this is a moving sensor, not a set of stations: the
/// lines of one station would hold a handful of points, so the structure is not used.
const MAX_STATIONS: usize = 1024;

/// Sorted elevations further apart than this (degrees) start a new beam when the beams are
/// recovered from the geometry: spinning sensors space their beams 0.1° or more apart, while
/// one beam's returns share its elevation to within hundredths of a degree.
const BEAM_GAP_DEGREES: f64 = 0.05;

/// Recovered beams are trusted only in this number: fewer is not a multi-beam scan, more is a
/// dense grid whose rows the gap cannot separate.
const PLAUSIBLE_BEAMS: std::ops::RangeInclusive<usize> = 4..=4096;

/// A line holding fewer returns than this is a fragment, not one beam's turn or one row.
pub const MIN_LINE_RETURNS: usize = 16;

/// The structure is trusted when at least this share of returns lie on lines that are not
/// fragments: where lines are found wrongly, returns scatter over many small ones.
const MIN_SHARE_ON_LINES: f32 = 0.9;

/// Why a scan's structure was not used, for the one line `prep` prints.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Unstructured {
    /// More distinct sensor positions than stations can be.
    MovingSensor { positions: usize },
    /// The elevations do not separate into a plausible number of beams at some station.
    NoSeparableBeams,
    /// Too few returns lie on lines that are more than fragments.
    FewReturnsOnLines { lines: usize, share: f32 },
}

impl std::fmt::Display for Unstructured {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::MovingSensor { positions } => {
                write!(f, "more than {positions} sensor positions, a moving sensor")
            }
            Self::NoSeparableBeams => write!(f, "the elevations separate into no plausible set of beams"),
            Self::FewReturnsOnLines { lines, share } => write!(
                f,
                "only {:.1} % of returns lie on lines of {MIN_LINE_RETURNS} or more ({lines} lines found)",
                share * 100.0
            ),
        }
    }
}

/// One scan line: its station, its mean elevation and its points in azimuth order.
#[derive(Clone, Debug, PartialEq)]
pub struct ScanLine {
    pub station: u32,
    /// Mean elevation above the station's horizon, radians.
    pub elevation: f32,
    /// Point indices sorted by azimuth.
    pub members: Vec<u32>,
    /// The median azimuth step between consecutive members, radians: the sensor's angular
    /// spacing along the line.
    pub azimuth_step: f32,
    /// The lines next below and above in elevation at the same station.
    pub below: Option<u32>,
    pub above: Option<u32>,
}

/// The scan structure of a set of points (local coordinates).
#[derive(Clone, Debug, PartialEq)]
pub struct ScanLines {
    pub lines: Vec<ScanLine>,
    /// Per point: its line.
    pub line_of: Vec<u32>,
    /// Per point: its azimuth around its station's vertical (+z) axis, radians.
    pub azimuth: Vec<f32>,
    /// Per point: its station's position.
    pub sensor: Vec<Vec3>,
    /// The standard deviation of the range noise, in scene units, measured along the lines
    /// (`scan::noise`), and never below `MIN_RANGE_NOISE`.
    pub range_noise: f32,
    /// Per station: where it stood and its lines, lowest first.
    pub stations: Vec<Station>,
}

/// One sensor position and the lines seen from it.
#[derive(Clone, Debug, PartialEq)]
pub struct Station {
    pub position: Vec3,
    /// Its lines in order of elevation.
    pub lines: Vec<u32>,
}

/// Near the poles of a station's sphere an angle spans ever more azimuth; beyond this cosine
/// of the elevation (about 87°) it is taken to span no more.
const MIN_AZIMUTH_COSINE: f32 = 0.05;

/// The rays of at most this many other stations, the nearest, pass judgement on a patch: a
/// map of sweeps along a street sees each surface from the few sweeps around it, and a sweep
/// far down the street adds nothing but time.
const JUDGING_STATIONS: usize = 8;

/// The least range noise assumed: returns are quantised (a millimetre for most sensors) and
/// a perfect simulated scan must still tolerate rounding.
const MIN_RANGE_NOISE: f32 = 0.001;

impl ScanLines {
    /// The structure of `points` seen from `sensors` (one per point, local coordinates), on
    /// the given `rings` or, without them, on beams recovered from each point's elevation;
    /// why not, when the structure cannot be trusted.
    pub fn new(points: &[Vec3], sensors: &[DVec3], rings: Option<&[u16]>) -> Result<Self, Unstructured> {
        let (station_of, stations) =
            stations(sensors).ok_or(Unstructured::MovingSensor { positions: MAX_STATIONS })?;
        let sensor: Vec<Vec3> = station_of.iter().map(|&s| stations[s as usize]).collect();
        let offsets: Vec<Vec3> = points.iter().zip(&sensor).map(|(&p, &s)| p - s).collect();
        let rings = match rings {
            Some(rings) => rings.to_vec(),
            None => recovered_beams(&offsets, &station_of, stations.len())
                .ok_or(Unstructured::NoSeparableBeams)?,
        };
        let azimuth: Vec<f32> = offsets.iter().map(|d| d.y.atan2(d.x)).collect();
        let (lines, line_of) = group_lines(&offsets, &station_of, &rings, &azimuth);
        let share = share_on_lines(&lines, points.len());
        if share < MIN_SHARE_ON_LINES {
            return Err(Unstructured::FewReturnsOnLines { lines: lines.len(), share });
        }
        let range_noise = range_noise(&lines, &offsets, &azimuth).max(MIN_RANGE_NOISE);
        let stations = stations_with_lines(&stations, &lines);
        Ok(Self { lines, line_of, azimuth, sensor, range_noise, stations })
    }

    /// The returns on lines of `MIN_LINE_RETURNS` or more.
    pub fn returns_on_lines(&self) -> usize {
        self.lines.iter().map(|line| line.members.len()).filter(|&n| n >= MIN_LINE_RETURNS).sum()
    }

    /// The lines above and below point `i`'s, and theirs above and below: up to four.
    pub fn nearby_lines(&self, i: usize) -> impl Iterator<Item = &ScanLine> {
        let line = &self.lines[self.line_of[i] as usize];
        let step = |index: Option<u32>, up: bool| {
            index.map(|l| &self.lines[l as usize]).and_then(|l| if up { l.above } else { l.below })
        };
        [line.below, line.above, step(line.below, false), step(line.above, true)]
            .into_iter()
            .flatten()
            .map(|l| &self.lines[l as usize])
    }

    /// The returns of point `i`'s station seen within `angle` (radians) of it in elevation and
    /// in azimuth: those whose rays may pass through a support of that angular size around it.
    pub fn returns_near_ray(&self, i: usize, angle: f32) -> Vec<u32> {
        let own = self.line_of[i];
        let elevation = self.lines[own as usize].elevation;
        let azimuth_reach = angle / elevation.cos().max(MIN_AZIMUTH_COSINE);
        let within = |l: &u32| (self.lines[*l as usize].elevation - elevation).abs() <= angle;
        let walk = |up: bool| {
            std::iter::successors(Some(own), move |&l| {
                let line = &self.lines[l as usize];
                if up { line.above } else { line.below }
            })
            .skip(1)
            .take_while(within)
        };
        let lines = std::iter::once(own).chain(walk(true)).chain(walk(false));
        let azimuth = self.azimuth[i];
        lines.flat_map(|l| self.members_within(l, azimuth, azimuth_reach)).collect()
    }

    /// The returns of the stations nearest `point`, other than `own`, whose rays may pass
    /// within `radius` of it: a surface seen from one sweep must leave room for what the
    /// other sweeps of a map saw through.
    pub fn other_stations_returns_near(&self, point: Vec3, radius: f32, own: u32) -> Vec<u32> {
        let mut nearest: Vec<(f32, u32)> = (0..self.stations.len() as u32)
            .filter(|&s| s != own)
            .map(|s| (self.stations[s as usize].position.distance_squared(point), s))
            .collect();
        if nearest.len() > JUDGING_STATIONS {
            nearest.select_nth_unstable_by(JUDGING_STATIONS, |a, b| a.0.total_cmp(&b.0));
            nearest.truncate(JUDGING_STATIONS);
        }
        nearest.into_iter().flat_map(|(_, s)| self.station_returns_near(s, point, radius)).collect()
    }

    /// The returns of `station` seen within the angle `radius` spans at `point`.
    fn station_returns_near(&self, station: u32, point: Vec3, radius: f32) -> Vec<u32> {
        let Station { position, lines } = &self.stations[station as usize];
        let offset = point - *position;
        let angle = (radius / offset.length().max(f32::MIN_POSITIVE)).min(1.0);
        let elevation = elevation(offset) as f32;
        let azimuth_reach = angle / elevation.cos().max(MIN_AZIMUTH_COSINE);
        let line_elevation = |l: &u32| self.lines[*l as usize].elevation;
        let first = lines.partition_point(|l| line_elevation(l) < elevation - angle);
        let azimuth = offset.y.atan2(offset.x);
        lines[first..]
            .iter()
            .take_while(|l| line_elevation(l) <= elevation + angle)
            .flat_map(|&l| self.members_within(l, azimuth, azimuth_reach))
            .collect()
    }

    /// The members of line `l` within `reach` of `azimuth`.
    fn members_within(&self, l: u32, azimuth: f32, reach: f32) -> impl Iterator<Item = u32> + '_ {
        let members = &self.lines[l as usize].members;
        let first = members.partition_point(|&m| self.azimuth[m as usize] < azimuth - reach);
        members[first..].iter().copied().take_while(move |&m| self.azimuth[m as usize] <= azimuth + reach)
    }

    /// The station point `i` was seen from.
    pub fn station_of(&self, i: usize) -> u32 {
        self.lines[self.line_of[i] as usize].station
    }

    /// The azimuth step along point `i`'s line, radians, when the line has one.
    pub fn azimuth_step(&self, i: usize) -> Option<f32> {
        Some(self.lines[self.line_of[i] as usize].azimuth_step).filter(|&step| step > 0.0)
    }

    /// The elevation step between point `i`'s line and the nearest line beside it, radians:
    /// the sensor's angular beam spacing there.
    pub fn beam_spacing(&self, i: usize) -> Option<f32> {
        let line = &self.lines[self.line_of[i] as usize];
        [line.below, line.above]
            .into_iter()
            .flatten()
            .map(|l| (self.lines[l as usize].elevation - line.elevation).abs())
            .reduce(f32::min)
    }
}

/// The share of `returns` on lines of `MIN_LINE_RETURNS` or more.
fn share_on_lines(lines: &[ScanLine], returns: usize) -> f32 {
    let on_lines: usize =
        lines.iter().map(|line| line.members.len()).filter(|&n| n >= MIN_LINE_RETURNS).sum();
    on_lines as f32 / returns.max(1) as f32
}

/// Per point its station index, and the stations; `None` for a moving sensor.
fn stations(sensors: &[DVec3]) -> Option<(Vec<u32>, Vec<Vec3>)> {
    let mut index: HashMap<[u64; 3], u32> = HashMap::new();
    let mut stations = Vec::new();
    let mut station_of = Vec::with_capacity(sensors.len());
    for sensor in sensors {
        let key = sensor.to_array().map(f64::to_bits);
        let next = index.len() as u32;
        let station = *index.entry(key).or_insert_with(|| {
            stations.push(sensor.as_vec3());
            next
        });
        if stations.len() > MAX_STATIONS {
            return None;
        }
        station_of.push(station);
    }
    Some((station_of, stations))
}

/// Each station's position with its lines, lowest first.
fn stations_with_lines(positions: &[Vec3], lines: &[ScanLine]) -> Vec<Station> {
    let mut stations: Vec<Station> =
        positions.iter().map(|&position| Station { position, lines: Vec::new() }).collect();
    for (l, line) in lines.iter().enumerate() {
        stations[line.station as usize].lines.push(l as u32);
    }
    for station in &mut stations {
        station.lines.sort_by(|&a, &b| lines[a as usize].elevation.total_cmp(&lines[b as usize].elevation));
    }
    stations
}

fn elevation(offset: Vec3) -> f64 {
    let horizontal = f64::from(offset.x).hypot(f64::from(offset.y));
    f64::from(offset.z).atan2(horizontal)
}

/// Beams recovered per station by splitting its sorted elevations at gaps wider than
/// `BEAM_GAP_DEGREES`; `None` when a station's beams are implausible in number, or too thick
/// for their spacing (`beams_are_thin`).
fn recovered_beams(offsets: &[Vec3], station_of: &[u32], station_count: usize) -> Option<Vec<u16>> {
    let mut by_station: Vec<Vec<(f64, u32)>> = vec![Vec::new(); station_count];
    for (i, (&offset, &station)) in offsets.iter().zip(station_of).enumerate() {
        by_station[station as usize].push((elevation(offset), i as u32));
    }
    let mut rings = vec![0u16; offsets.len()];
    for mut members in by_station {
        members.sort_by(|a, b| a.0.total_cmp(&b.0));
        let gap = BEAM_GAP_DEGREES.to_radians();
        let mut beam = 0usize;
        let mut spans = vec![(members.first().map_or(0.0, |m| m.0), members.first().map_or(0.0, |m| m.0))];
        for pair in members.windows(2) {
            if pair[1].0 - pair[0].0 > gap {
                beam += 1;
                spans.push((pair[1].0, pair[1].0));
            }
            spans[beam].1 = pair[1].0;
            rings[pair[1].1 as usize] = u16::try_from(beam).ok()?;
        }
        let plausible = PLAUSIBLE_BEAMS.contains(&(beam + 1)) && beams_are_thin(&spans);
        if !members.is_empty() && !plausible {
            return None;
        }
    }
    Some(rings)
}

/// One beam's returns share its elevation to hundredths of a degree, and beams lie tenths
/// apart: recovered beams whose median elevation span reaches half their median spacing are
/// bands of many beams run together (a sweep whose beams overlap in elevation), not beams.
fn beams_are_thin(spans: &[(f64, f64)]) -> bool {
    let median = |mut values: Vec<f64>| {
        let middle = values.len() / 2;
        values.select_nth_unstable_by(middle, f64::total_cmp).1.to_owned()
    };
    let thickness = median(spans.iter().map(|(low, high)| high - low).collect());
    let spacing =
        median(spans.windows(2).map(|pair| (pair[1].0 + pair[1].1 - pair[0].0 - pair[0].1) / 2.0).collect());
    thickness < 0.5 * spacing
}

/// Lines keyed by (station, ring), members sorted by azimuth, linked to their elevation
/// neighbours at the same station.
fn group_lines(
    offsets: &[Vec3],
    station_of: &[u32],
    rings: &[u16],
    azimuth: &[f32],
) -> (Vec<ScanLine>, Vec<u32>) {
    let mut index: HashMap<(u32, u16), u32> = HashMap::new();
    let mut lines: Vec<ScanLine> = Vec::new();
    let mut elevation_sums: Vec<f64> = Vec::new();
    let mut line_of = Vec::with_capacity(offsets.len());
    for (i, (&station, &ring)) in station_of.iter().zip(rings).enumerate() {
        let next = lines.len() as u32;
        let line = *index.entry((station, ring)).or_insert_with(|| {
            lines.push(ScanLine {
                station,
                elevation: 0.0,
                members: Vec::new(),
                azimuth_step: 0.0,
                below: None,
                above: None,
            });
            elevation_sums.push(0.0);
            next
        });
        lines[line as usize].members.push(i as u32);
        elevation_sums[line as usize] += elevation(offsets[i]);
        line_of.push(line);
    }
    for (line, sum) in lines.iter_mut().zip(elevation_sums) {
        line.elevation = (sum / line.members.len() as f64) as f32;
        line.members.sort_by(|&a, &b| azimuth[a as usize].total_cmp(&azimuth[b as usize]));
        line.azimuth_step = median_step(&line.members, azimuth);
    }
    link_by_elevation(&mut lines);
    (lines, line_of)
}

/// The median of the positive azimuth steps between consecutive `members` (sorted by
/// azimuth); 0 when there are none.
fn median_step(members: &[u32], azimuth: &[f32]) -> f32 {
    let mut steps: Vec<f32> = members
        .windows(2)
        .map(|pair| azimuth[pair[1] as usize] - azimuth[pair[0] as usize])
        .filter(|&step| step > 0.0)
        .collect();
    if steps.is_empty() {
        return 0.0;
    }
    let middle = steps.len() / 2;
    *steps.select_nth_unstable_by(middle, f32::total_cmp).1
}

fn link_by_elevation(lines: &mut [ScanLine]) {
    let mut order: Vec<u32> = (0..lines.len() as u32).collect();
    order.sort_by(|&a, &b| {
        let (a, b) = (&lines[a as usize], &lines[b as usize]);
        a.station.cmp(&b.station).then(a.elevation.total_cmp(&b.elevation))
    });
    for pair in order.windows(2) {
        let (low, high) = (pair[0] as usize, pair[1] as usize);
        if lines[low].station == lines[high].station {
            lines[low].above = Some(pair[1]);
            lines[high].below = Some(pair[0]);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Three beams at -2°, 0° and 2°, 90 returns each on a cylinder of radius 10 around the
    /// origin.
    fn three_beams() -> Vec<Vec3> {
        [-2.0f32, 0.0, 2.0]
            .iter()
            .flat_map(|&elevation| {
                (0..90).map(move |step| {
                    let azimuth = (step as f32 * 4.0).to_radians();
                    let e = elevation.to_radians();
                    Vec3::new(azimuth.cos() * e.cos(), azimuth.sin() * e.cos(), e.sin()) * 10.0
                })
            })
            .collect()
    }

    #[test]
    fn another_station_finds_its_own_returns_around_a_point_and_not_the_askers() {
        // The same three beams seen from two stations 5 m apart along x.
        let near = three_beams();
        let far: Vec<Vec3> = near.iter().map(|&p| p + Vec3::X * 5.0).collect();
        let points = [near.clone(), far].concat();
        let sensors: Vec<DVec3> =
            (0..points.len()).map(|i| if i < near.len() { DVec3::ZERO } else { DVec3::X * 5.0 }).collect();
        let rings: Vec<u16> = (0..points.len()).map(|i| ((i % 270) / 90) as u16).collect();
        let scan = ScanLines::new(&points, &sensors, Some(&rings)).unwrap();
        assert_eq!(scan.stations.len(), 2);
        // Point 100 (middle beam, 40° round) from the first station: the second station's
        // rays toward it come from its middle beam, around the same spot on its own cylinder.
        let (own, point) = (scan.station_of(100), points[100]);
        let others = scan.other_stations_returns_near(point, 0.5, own);
        assert!(!others.is_empty());
        for j in &others {
            assert_ne!(scan.station_of(*j as usize), own);
            let toward = (points[*j as usize] - Vec3::X * 5.0).normalize();
            let angle = toward.angle_between((point - Vec3::X * 5.0).normalize());
            assert!(angle <= 0.5 / (point - Vec3::X * 5.0).length() * 1.5, "{j} at {angle}");
        }
        assert!(
            scan.other_stations_returns_near(point, 0.5, 1 - own)
                .iter()
                .all(|&j| scan.station_of(j as usize) == own)
        );
    }

    #[test]
    fn beams_are_recovered_from_elevations_and_linked_in_order() {
        let points = [three_beams(), three_beams()].concat();
        let too_few = ScanLines::new(&points, &vec![DVec3::ZERO; points.len()], None);
        assert_eq!(
            too_few,
            Err(Unstructured::NoSeparableBeams),
            "three beams are not a plausible multi-beam scan"
        );
        let rings: Vec<u16> = (0..points.len()).map(|i| ((i % 270) / 90) as u16).collect();
        let scan = ScanLines::new(&points, &vec![DVec3::ZERO; points.len()], Some(&rings)).unwrap();
        assert_eq!(scan.lines.len(), 3);
        let middle = &scan.lines[scan.line_of[100] as usize];
        assert_eq!(middle.members.len(), 180);
        assert_eq!(scan.nearby_lines(100).count(), 2);
        assert!((scan.beam_spacing(100).unwrap() - 2f32.to_radians()).abs() < 1e-4);
        let sorted =
            middle.members.windows(2).all(|w| scan.azimuth[w[0] as usize] <= scan.azimuth[w[1] as usize]);
        assert!(sorted);
    }

    #[test]
    fn recovered_beams_match_the_elevations() {
        let points: Vec<Vec3> = (0..8)
            .flat_map(|beam| {
                (0..50).map(move |step| {
                    let (azimuth, e) =
                        ((step as f32 * 7.0).to_radians(), (beam as f32 * 0.4 - 1.4).to_radians());
                    Vec3::new(azimuth.cos() * e.cos(), azimuth.sin() * e.cos(), e.sin())
                        * (5.0 + step as f32 * 0.1)
                })
            })
            .collect();
        let scan = ScanLines::new(&points, &vec![DVec3::new(0.0, 0.0, 0.0); points.len()], None).unwrap();
        assert_eq!(scan.lines.len(), 8);
        for (i, &line) in scan.line_of.iter().enumerate() {
            assert_eq!(scan.lines[line as usize].members.len(), 50, "point {i}");
        }
    }

    #[test]
    fn bands_of_beams_run_together_are_not_beams() {
        let spread: Vec<Vec3> = (0..4000)
            .map(|i| {
                let (azimuth, e) = ((i as f32 * 0.37).to_radians(), (i as f32 * 0.005 - 10.0).to_radians());
                let e = if (i / 800) % 2 == 0 { e } else { e + 0.2f32.to_radians() };
                Vec3::new(azimuth.cos() * e.cos(), azimuth.sin() * e.cos(), e.sin()) * 10.0
            })
            .collect();
        let found = ScanLines::new(&spread, &vec![DVec3::ZERO; spread.len()], None);
        assert_eq!(found, Err(Unstructured::NoSeparableBeams));
    }

    #[test]
    fn a_moving_sensor_has_no_structure() {
        let points = vec![Vec3::X; MAX_STATIONS + 2];
        let sensors: Vec<DVec3> = (0..points.len()).map(|i| DVec3::new(i as f64, 0.0, 0.0)).collect();
        assert!(matches!(ScanLines::new(&points, &sensors, None), Err(Unstructured::MovingSensor { .. })));
    }

    #[test]
    fn returns_scattered_over_fragments_are_not_a_structure() {
        let points = three_beams();
        let rings: Vec<u16> = (0..points.len()).map(|i| (i / 4) as u16).collect();
        let scattered = ScanLines::new(&points, &vec![DVec3::ZERO; points.len()], Some(&rings));
        assert!(matches!(scattered, Err(Unstructured::FewReturnsOnLines { share, .. }) if share == 0.0));
    }
}
