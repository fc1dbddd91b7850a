use super::*;

fn shipped(relative: &str, name: &str) -> Case {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../cases").join(relative);
    let text = std::fs::read_to_string(&path).unwrap();
    // the first `name = ` is the [case] name
    let text = text.replacen(&format!("name = \"{}\"", Case::from_toml(&text, &path).unwrap().case.name), &format!("name = \"{name}\""), 1);
    Case::from_toml(&text, &path).unwrap()
}

fn demo() -> Case {
    shipped("pour.toml", "demo")
}

fn sample() -> State {
    State { time: 0.1 + 0.2, step: 7, dt: 1.0 / 3.0, rotor_angle: -std::f64::consts::PI * 1e-17, ..State::default() }
}

fn tmp(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("spillage-ckpt-{}-{name}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir.join("state.ckpt")
}

#[test]
fn round_trips_bit_for_bit() {
    let path = tmp("rt");
    let state = sample();
    write(&path, &demo(), &state).unwrap();
    let back = read_stored(&path, Some("demo")).unwrap().state;
    assert_eq!(back.time.to_bits(), state.time.to_bits());
    assert_eq!(back.dt.to_bits(), state.dt.to_bits());
    assert_eq!(back.rotor_angle.to_bits(), state.rotor_angle.to_bits());
    assert_eq!(back, state);
    assert!(!path.with_extension("tmp").exists(), "temporary file left behind");
}

#[test]
fn refuses_damaged_truncated_foreign_and_wrong_case() {
    let path = tmp("bad");
    write(&path, &demo(), &sample()).unwrap();
    let good = std::fs::read(&path).unwrap();

    let mut flipped = good.clone();
    let last = flipped.len() - 9;
    flipped[last] ^= 0x40;
    std::fs::write(&path, &flipped).unwrap();
    assert!(matches!(read_stored(&path, None), Err(CheckpointError::Damaged { .. })));

    std::fs::write(&path, &good[..good.len() - 3]).unwrap();
    assert!(matches!(read_stored(&path, None), Err(CheckpointError::Damaged { .. })));

    std::fs::write(&path, b"hello world\n").unwrap();
    assert!(matches!(read_stored(&path, None), Err(CheckpointError::NotACheckpoint { .. })));

    std::fs::write(&path, &good).unwrap();
    let err = read_stored(&path, Some("other")).unwrap_err();
    assert!(err.to_string().contains("\"other\""), "{err}");
}

/// Issue 14 item 2: a DEM `pour` checkpoint was accepted by a fluid case named `pour`, and a
/// fluid checkpoint by a DEM case; the refusal names the phase.
#[test]
fn a_checkpoint_of_another_phase_is_refused_naming_the_phase() {
    let dem = shipped("pour.toml", "pour");
    let fluid = shipped("verification/fluid/taylor_green.toml", "pour");
    let path = tmp("phases");
    write(&path, &dem, &sample()).unwrap();
    let err = read(&path, &fluid).unwrap_err().to_string();
    assert!(err.contains("the checkpoint has a particle phase but the case has none"), "{err}");
    assert!(err.contains("the checkpoint has no fluid phase, but the case has one"), "{err}");
    write(&path, &fluid, &sample()).unwrap();
    let err = read(&path, &dem).unwrap_err().to_string();
    assert!(err.contains("the checkpoint has a fluid phase but the case has none"), "{err}");
}

/// Same phases, other walls and materials: a sphere–wall checkpoint read by the moving-disc case.
#[test]
fn a_checkpoint_of_other_walls_or_materials_is_refused_naming_them() {
    let wall = shipped("verification/dem/hertz_sphere_wall.toml", "same");
    let disc = shipped("verification/dem/moving_wall_disc.toml", "same");
    let path = tmp("walls");
    write(&path, &wall, &sample()).unwrap();
    let err = read(&path, &disc).unwrap_err().to_string();
    assert!(err.contains("the walls: the checkpoint has walls"), "{err}");
    // the case itself reads its own checkpoint (its state is valid: no particles yet)
    assert!(matches!(read(&path, &wall), Err(CheckpointError::Invalid { .. }) | Ok(_)));
}

/// Issue 14 item 2: a payload replaced under a recomputed checksum loaded a NaN time.
#[test]
fn a_forged_payload_with_a_nan_time_is_refused_before_any_step() {
    let case = demo();
    let path = tmp("forged");
    write(&path, &case, &sample()).unwrap();
    let forged = State { time: f64::NAN, ..sample() };
    let payload = postcard::to_stdvec(&(Fingerprint::of_case(&case), &forged)).unwrap();
    let mut bytes = format!("spillage-checkpoint {VERSION} demo\n").into_bytes();
    bytes.extend((payload.len() as u64).to_le_bytes());
    bytes.extend(&payload);
    bytes.extend(fnv1a(&payload).to_le_bytes());
    std::fs::write(&path, &bytes).unwrap();
    let err = read(&path, &case).unwrap_err().to_string();
    assert!(err.contains("time = NaN"), "{err}");
    assert!(err.contains("cannot be continued"), "{err}");
}

/// A contact history out of order (or with a contact twice) is refused, naming the two
/// contacts: the DEM phases walk it in order, and a new neighbour list's pieces start their
/// walks by bisection, which an unsorted history would misdirect.
#[test]
fn a_contact_history_out_of_order_is_refused_naming_the_contacts() {
    let case = demo();
    let mut state = sample();
    crate::particles::dem_setup::DemSetup::new(&case, &mut state).unwrap();
    let contact = |particle: u64, partner: u64| crate::particles::ContactRecord {
        particle,
        partner: crate::particles::Partner::Particle(partner),
        tangential_overlap: Default::default(),
        damping_ratio: 0.1,
        approach_speed: 0.5,
        normal: crate::particles::state::Vec3::x(),
        start_time: 0.0,
        restitution: 0.5,
        normal_impulse: 0.0,
    };
    let path = tmp("unsorted-contacts");
    for (contacts, listed) in [
        (vec![contact(2, 5), contact(1, 7)], "particle 2 with Particle(5) before particle 1 with Particle(7)"),
        (vec![contact(1, 3), contact(1, 3)], "particle 1 with Particle(3) before particle 1 with Particle(3)"),
    ] {
        state.particles.as_mut().expect("the pour's particles").contacts = contacts;
        write(&path, &case, &state).unwrap();
        let err = read(&path, &case).unwrap_err().to_string();
        assert!(err.contains(listed) && err.contains("sorted by particle, then partner"), "{err}");
    }
    state.particles.as_mut().unwrap().contacts = vec![contact(1, 3), contact(1, 7), contact(2, 5)];
    write(&path, &case, &state).unwrap();
    read(&path, &case).unwrap();
}

/// Issue 14 item 2: a damaged checkpoint printed binary payload bytes as "the case name".
#[test]
fn a_damaged_header_never_prints_binary_bytes() {
    let path = tmp("binary");
    let mut bytes = b"spillage-checkpoint 5 demo".to_vec();
    bytes.extend([0u8, 1, 2, 0xff, 0xfe, 7, 27, b'x', b'\n']);
    bytes.extend([0u8; 40]);
    std::fs::write(&path, &bytes).unwrap();
    let err = read(&path, &demo()).unwrap_err().to_string();
    assert!(!err.chars().any(|c| c.is_control() || c == '\u{fffd}'), "{err:?}");
    assert!(err.contains("damaged"), "{err}");
    // a name of valid text but a payload in the header line (no newline for 512 bytes)
    let mut long = b"spillage-checkpoint 5 demo".to_vec();
    long.extend(std::iter::repeat_n(b'a', 2000));
    std::fs::write(&path, &long).unwrap();
    let err = read(&path, &demo()).unwrap_err().to_string();
    assert!(err.len() < 200 && err.contains("no end to its header line"), "{err}");
    // a wrong name is shown escaped and cut
    let name = format!("demo\u{7f}{}", "y".repeat(100));
    let mut other = format!("spillage-checkpoint 5 {name}\n").into_bytes();
    other.extend([0u8; 16]);
    std::fs::write(&path, &other).unwrap();
    let err = read(&path, &demo()).unwrap_err().to_string();
    assert!(!err.chars().any(char::is_control) && err.len() < 250, "{err:?}");
}

#[test]
fn an_older_version_says_rerun_from_the_start() {
    let path = tmp("old");
    std::fs::write(&path, b"spillage-checkpoint 4 demo\n\0\0\0\0\0\0\0\0\0\0\0\0\0\0\0\0").unwrap();
    let err = read(&path, &demo()).unwrap_err().to_string();
    assert!(err.contains("written by an older spillage") && err.contains("rerun the case from the start"), "{err}");
}

/// The modifier weighs the checkpoint's α_c time levels: a restart with another one is refused,
/// naming it; one that never set it (modifier 1) still matches a case that sets 1.
#[test]
fn a_checkpoint_of_another_particle_modifier_is_refused() {
    let case = demo();
    let mut four = case.clone();
    four.particles.as_mut().unwrap().modifier = 4.0;
    let err = Fingerprint::of_case(&four).compare(&Fingerprint::of_case(&case)).unwrap_err();
    assert!(err.contains("each for 4 real ones"), "{err}");
    let mut one = case.clone();
    one.particles.as_mut().unwrap().modifier = 1.0;
    assert!(Fingerprint::of_case(&one).compare(&Fingerprint::of_case(&case)).is_ok());
}

/// The blade lean reshapes the head's mesh: a restart of a backward head's checkpoint with a
/// forward head is refused; a backward head hashes as it did before the key existed (its
/// values without `blade_sweep`), so older checkpoints of the shipped head still match.
#[test]
fn a_checkpoint_of_another_blade_lean_is_refused_and_the_default_hashes_as_before() {
    let head = shipped("cutter_head.toml", "demo");
    let mut forward = head.clone();
    forward.cutter_head.as_mut().unwrap().blade_sweep = crate::cutter_head::BladeSweep::Forward;
    let err = Fingerprint::of_case(&forward).compare(&Fingerprint::of_case(&head)).unwrap_err();
    assert!(err.contains("the mesh"), "{err}");
    let values = super::fingerprint::mesh_values(&head);
    assert!(!values.contains("blade_sweep") && values.contains("blade_twist: 40.0, ring_inner_radius"), "{values}");
    assert!(super::fingerprint::mesh_values(&forward).contains("blade_sweep: Forward"));
}
