//! The project's own numbers 900–944; the checks that read the files AXCFIL names (213, 214, 223,
//! 943) or several records (126, 207); and how diagnostics name section, process and the nearest name.

use super::*;

case!(
    p900_non_ascii,
    BASE,
    [("NAS=X", "NAS=Х")],
    900,
    [("Х", 0), ("Х", 0)],
    [151, 169]
);
case!(
    p901_boolean,
    BASE,
    [("GM0=10000", "FBF=,,U230K0,2\nGM0=10000")],
    901,
    [("U230K0,^2", 0)],
    []
);
case!(
    p917_nbp_zero,
    BASE,
    [("NBP=1,", "NBP=0,")],
    917,
    [("NBP=^0", 0)],
    []
);
case!(
    p918_nbp_extension,
    BASE,
    [("NBP=1,ECDF", "NBP=1,5")],
    918,
    [("NBP=1,^5", 0)],
    [134, 135, 148, 189, 935]
);
case!(
    p920_no_process,
    BASE,
    [("PRO=1\nIN1", "IN0=1,,,2,1\nPRO=1\nIN1")],
    920,
    [("IN0", 0)],
    []
);
case!(
    p921_process_twice,
    BASE,
    [("CAS=1,XZS,2", "CAS=1,XZS,2\nPRO=1")],
    921,
    [("PRO=1", 1)],
    []
);
case!(
    p922_process_incomplete,
    BASE,
    [("NBP=1,", "NBP=2,")],
    922,
    [("*1", 0)],
    []
);
case!(
    p923_com_process,
    BASE,
    [("CAS=1", "COM=1,S\nCAS=1")],
    923,
    [("COM", 0)],
    [118]
);
case!(
    p925_axis_letter,
    BASE,
    [
        ("IN1=1,XZ,", "IN1=1,KZ,"),
        ("CAS=1,XZS", "CAS=1,KZS"),
        ("NAS=X", "NAS=K")
    ],
    925,
    [("NAS=K", 0)],
    []
);
case!(
    p926_block_num,
    BASE,
    [("S,2,16", "S,2,1")],
    926,
    [("IN1", 0)],
    []
);
case!(
    p927_cas_order,
    BASE,
    [("CAS=1,XZS", "CAS=1,ZXS")],
    927,
    [("CAS", 0)],
    [928]
);
case!(
    p928_nas_order,
    BASE,
    [("CAS=1,XZS", "CAS=1,XSZ")],
    928,
    [("NAS=Z", 0)],
    []
);
case!(
    p929_range,
    BASE,
    [("PAS=5000,5,,", "PAS=-5000,5,,")],
    929,
    [("-5000", 0)],
    []
);
case!(
    p930_tpa_bits,
    BASE,
    [("TPA=41,", "TPA=20041,")],
    930,
    [("20041", 0)],
    []
);
case!(
    p931_type_forbids,
    BASE,
    [("SRV=,,", "SRV=1,,")],
    931,
    [("SRV=1", 0)],
    []
);
case!(
    p932_tsm_missing,
    BASE,
    [("TSM=4,17\n", "")],
    932,
    [("TPA=820", 0)],
    []
);
case!(
    p934_section3,
    BASE,
    [(
        "*3\n",
        "*3\nPRO=1\nNAS=Z\nPAS=-1\nE001=0\nE002=0.002\nNM0=E001\n"
    )],
    934,
    [("-1", 0)],
    [173, 175]
);
case!(
    p935_ecdf_form,
    BASE,
    [
        ("NBP=1,ECDF", "NBP=1,0"),
        ("GAS=0.004,0.002,,", "GAS=0.004,0.002"),
        ("GAS=0.006,0.002,,", "GAS=0.006,0.002"),
        ("GAS=,,,", "GAS=,"),
        ("PAS=5000,5,,", "PAS=5000,5"),
        ("PAS=5000,10,,", "PAS=5000,10"),
        ("PAS=4096,1,,", "PAS=4096,1"),
        ("GM0=10000,7.5,20,,", "GM0=10000,7.5,20"),
        ("GM0=12000,7.5,20,,", "GM0=12000,7.5,20"),
        ("GM1=3000,8.5,6,,", "GM1=3000,8.5,6")
    ],
    935,
    [("POM=0.5,100^,", 0)],
    [189]
);
case!(
    p936_signal_twice,
    BASE,
    [("GAS=0.004,0.002,,", "GAS=0.004,0.002,U220K0,U220K0")],
    936,
    [("GAS=0.004", 0)],
    []
);
case!(
    p938_interpolator_kind,
    BASE,
    [("TPA=41,", "TPA=2,"), ("SRV=.5,2,10", "SRV=,,")],
    938,
    [("NAS=X", 0)],
    []
);
case!(
    p940_handwheel_interpolated,
    BASE,
    [("GM0=10000", "HWC=Z,U140K0\nGM0=10000")],
    940,
    [("HWC", 0)],
    []
);
case!(
    p941_com_axis,
    BASE,
    [
        ("NBP=1,", "NBP=2,"),
        ("*2", "PRO=2\nCOM=1,Q\nIN2=1,A,,2,16\nCAS=1,A,2\n*2")
    ],
    941,
    [("Q", 0)],
    [169]
);
case!(
    p942_section1_twice,
    BASE,
    [("TIM=1,0,0,0,0", "TIM=1,0,0,0,0\nTIM=1,0,0,0,0")],
    942,
    [("TIM", 1)],
    []
);
#[test]
fn p944_file_ref() {
    let src = magazine("FTP=BAD\n");
    let (line, col) = at(&src, "BAD", 0);
    assert_eq!(diags(&src), [(944, line, col)]);
}

/// A PTP tool magazine T in process 2 for the side-file rules.
fn magazine(ftp: &str) -> String {
    edit(
        BASE,
        &[
            ("NBP=1,", "NBP=2,"),
            ("*2", "PRO=2\nIN2=1,T,,2,1\nCAS=1,T,2\n*2"),
            (
                "*3",
                &format!(
                    "PRO=2\nNAS=T\nTPA=2,\nNTC=5,5\nRAP=600,10\nGAS=,,,\nPAS=6000,4,1,0\nPOS=.1,10\nSRV=,,\nMAN=400,10\nGM0=600,7.5,7,,\n{ftp}*3"
                ),
            ),
        ],
    )
}

fn with_side(src: &str, side: &dyn Fn(&FileRef) -> Option<Vec<u8>>) -> Vec<(u32, u32, u32)> {
    let (f, mut d) = read("AXCFIL", src.as_bytes());
    d.extend(axcfil::validate_with(&f, side, true).1);
    d.iter().map(|d| (d.code, d.line, d.column)).collect()
}

#[test]
fn e213_ftp_file_incorrect_and_fx39_side_file() {
    let src = magazine("FTP=TABTT1/MP0\n");
    let (line, col) = at(&src, "FTP", 0);
    let good = "0 0 pos 0\n1 1.5 pos 1\n2 2 pos 2\n3 3 pos 3\n";
    assert_eq!(
        with_side(&src, &|f: &FileRef| (f.file == "TABTT1" && f.mp == 0)
            .then(|| good.as_bytes().to_vec())),
        []
    );
    let three = "0 0\n1 1.5\n2 2\n";
    assert_eq!(
        with_side(&src, &|_: &FileRef| Some(three.as_bytes().to_vec())),
        [(213, line, col)]
    );
    let jump = "0 0\n1 1.5\n2 3.5\n3 3\n";
    assert_eq!(
        with_side(&src, &|_: &FileRef| Some(jump.as_bytes().to_vec())),
        [(213, line, col)]
    );
}

#[test]
fn e214_ftp_file_missing() {
    let src = magazine("FTP=TABTT1/MP0\n");
    let (line, col) = at(&src, "FTP", 0);
    assert_eq!(with_side(&src, &|_: &FileRef| None), [(214, line, col)]);
}

#[test]
fn e223_fopp_signal() {
    let src = magazine("FOPP=I0A0\n");
    let (line, col) = at(&src, "I0A0", 0);
    assert_eq!(diags(&src), [(223, line, col)]);
    assert_eq!(diags(&magazine("FOPP=I222K16\n")), []);
}

#[test]
fn p943_feg_file() {
    let src = edit(
        BASE,
        &[(
            "*3\n",
            "*3\nPRO=1\nNAS=Z\nPAS=50\nFEG=COMPZ/MP2\nNM0=E002\n",
        )],
    );
    let (line, col) = at(&src, "NAS=Z", 1);
    assert_eq!(with_side(&src, &|_: &FileRef| None), [(943, line, col)]);
    let ok = |f: &FileRef| {
        (f.file == "COMPZ" && f.mp == 2).then(|| b"E001 = 0.1\nE002 = 0.11\n".to_vec())
    };
    assert_eq!(with_side(&src, &ok), []);
    let bad = |_: &FileRef| Some(b"E001 = 0.1\nE001 = 0.11\n".to_vec());
    assert_eq!(with_side(&src, &bad), [(943, line, col), (177, line, col)]);
}

#[test]
fn e126_servo_ticks_differ() {
    let src = magazine("")
        .replace("CAS=1,T,2", "CAS=1,T,4")
        .replace("IN2=1,T,,2,1", "IN2=1,T,,4,1");
    let (line, col) = at(&src, "CAS=1,T", 0);
    assert_eq!(diags(&src), [(126, line, col)]);
}

#[test]
fn e207_cub_axes() {
    let axis = |n: char, k: u32| {
        format!(
            "NAS={n}\nTPA=1,\nNTC={k},{k}\nRAP=12000,800\nGAS=,,,\nPAS=5000,10,,\nPOS=.005,2\nSRV=.5,2,10\nMAN=2000,200\nGM0=12000,7.5,20,,\nCUB=1,-1,1\n"
        )
    };
    let src = edit(
        BASE,
        &[
            ("IN1=1,XZ,", "IN1=1,XZYW,"),
            ("CAS=1,XZS,2", "CAS=1,XZYWS,2"),
            ("GM0=10000,7.5,20,,\n", "GM0=10000,7.5,20,,\nCUB=1,-1,1\n"),
            ("GM0=12000,7.5,20,,\n", "GM0=12000,7.5,20,,\nCUB=1,-1,1\n"),
            ("NAS=S", &format!("{}{}NAS=S", axis('Y', 5), axis('W', 6))),
        ],
    );
    let (line, col) = at(&src, "CUB", 3);
    assert_eq!(diags(&src), [(207, line, col)]);
}

#[test]
fn slave_axis_example_is_valid() {
    assert_eq!(diags(&slave()), []);
}

/// Diagnostics about section-1 records found while checking an axis carry section 1.
#[test]
fn block_num_diagnostic_names_section_one() {
    let src = edit(BASE, &[("S,2,16", "S,2,1")]);
    let (f, _) = read("AXCFIL", src.as_bytes());
    let d = axcfil::validate(&f).1;
    assert_eq!(
        d.iter()
            .map(|d| (d.code, d.section, d.process))
            .collect::<Vec<_>>(),
        [(926, Some(1), Some(1))]
    );
}

case!(
    p945_slave_homing,
    &slave(),
    [("POS=.005,2", "MCZ=I0A7,0,300\nPOS=.005,2")],
    945,
    [("MCZ=I0A8", 0)],
    []
);
case!(
    p931_vgas_without_backlash,
    BASE,
    [("GAS=0.004,0.002,,", "GAS=,0.002,,\nVGAS=3,U180K0,U180K1")],
    931,
    [("VGAS", 0)],
    []
);
case!(
    p929_kkrm_hdbrp,
    BASE,
    [
        ("TPA=41,", "TPA=40041,"),
        ("POS=.005,2", "MCZ=,0,200,0,0.02\nPOS=.005,2")
    ],
    929,
    [("MCZ", 0)],
    []
);

#[test]
fn slave_with_the_masters_homing_is_valid() {
    let src = edit(&slave(), &[("POS=.005,2", "MCZ=I0A7,0,200\nPOS=.005,2")]);
    assert_eq!(diags(&src), []);
    let vgas = edit(BASE, &[("GM0=10000", "VGAS=3,U180K0,U180K1\nGM0=10000")]);
    assert_eq!(diags(&vgas), []);
}

/// Diagnostics carry the section and process they were found in.
#[test]
fn diagnostics_name_section_and_process() {
    let src = edit(
        BASE,
        &[
            ("MAN=2000,200", "MAN=20000,200"),
            ("TIM=1,", "TIM=64,"),
            ("*3\n", "*3\nPRO=1\nNAS=Z\nPAS=50\nE002=0\nE001=0\n"),
        ],
    );
    let (f, mut d) = read("AXCFIL", src.as_bytes());
    d.extend(axcfil::validate(&f).1);
    let got: Vec<(u32, Option<u32>, Option<u32>)> =
        d.iter().map(|d| (d.code, d.section, d.process)).collect();
    assert_eq!(
        got,
        [
            (101, Some(1), None),
            (174, Some(3), Some(1)),
            (175, Some(3), Some(1)),
            (139, Some(2), Some(1))
        ]
    );
}

/// NBP=7 on a file that opens one process: one error, the real cause, with the likely intent in
/// its hint; no follow-on errors about processes 2..5 (issue 12: 25 errors and 8 warnings before).
#[test]
fn nbp_too_many_is_one_error_with_the_processes_of_the_file_as_hint() {
    let src = edit(BASE, &[("NBP=1,", "NBP=7,")]);
    let (f, mut d) = read("AXCFIL", src.as_bytes());
    let (model, v) = axcfil::validate(&f);
    d.extend(v);
    let got: Vec<_> = d
        .iter()
        .map(|d| {
            (
                d.code,
                d.line,
                d.column,
                d.message.as_str(),
                d.hint.as_str(),
            )
        })
        .collect();
    assert_eq!(
        got,
        [(
            183,
            2,
            5,
            "NBP declares 7 processes",
            "at most 5 processes are allowed; section 1 opens processes up to PRO=1: write NBP=1"
        )]
    );
    assert_eq!(model.nbp, 1);
}

/// A misspelled instruction gets "did you mean" with the nearest instruction of its section (the
/// axis then lacks RAP: 137 is the consequence, reported at the axis).
#[test]
fn misspelled_instruction_suggests_the_nearest_name() {
    let src = edit(BASE, &[("RAP=10000,800", "RPA=10000,800")]);
    let (f, mut d) = read("AXCFIL", src.as_bytes());
    d.extend(axcfil::validate(&f).1);
    let got: Vec<_> = d
        .iter()
        .map(|d| {
            (
                d.code,
                d.line,
                d.column,
                d.message.as_str(),
                d.hint.as_str(),
            )
        })
        .collect();
    assert_eq!(
        got,
        [
            (
                6,
                12,
                1,
                "instruction RPA is not allowed in AXCFIL section 2",
                "did you mean `RAP`? section 2 allows TPA NTC RAP GAS VGAS PAS SKW MCZ POS SRV MAN MSS GMxx FRC LOP LOx MFC AFC CUB SWx TSM ASM POM ADP ZNO FBF HWC ATR GRA FOPP FTP ADG LAS FQF"
            ),
            (
                137,
                9,
                1,
                "axis X has no RAP",
                "declare rapid speed and acceleration, e.g. `RAP=12000,800`"
            )
        ]
    );
}
