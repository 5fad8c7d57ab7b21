//! One test per G26–G29 operation code, each run by the interpreter and by native code, plus the
//! test vectors of the parameters-cycles spec §4.3 and §4.9.

use crate::common;

use common::*;
use partprogram::{Backend, PlanOptions};

/// Runs `src` (a MEFI block list after `%1`) with both backends, asserts equal parameters, returns them.
fn params(src: &str) -> [i64; 96] {
    let text = format!("%1\n{src}\nN9999 M30\n");
    let a = run(
        &mill(),
        &text,
        PlanOptions {
            backend: Backend::Interpreter,
            ..PlanOptions::default()
        },
    )
    .params;
    let b = run(
        &mill(),
        &text,
        PlanOptions {
            backend: Backend::Native,
            ..PlanOptions::default()
        },
    )
    .params;
    assert_eq!(a, b, "native and interpreter differ for {src}");
    a
}

#[test]
fn op03_multiply_raw_and_decimal() {
    let p = params("N1 R12=3 R10=100. G26 R5=-03121015");
    assert_eq!(p[15], 300_000);
    let p = params("N1 R18=34.000 R26=1.5 G26 R5=+03182641");
    assert_eq!(p[41], 51_000);
}

#[test]
fn l9001_return_block_sequence() {
    let p = params("N1 R12=2 R10=100. G28 R5=-41120012 R6=-03121015 R7=08150015");
    assert_eq!(p[12], 3);
    assert_eq!(p[15], -300_000);
}

#[test]
fn op00_copy() {
    assert_eq!(params("N1 R13=3 G26 R5=00130019")[19], 3);
}

#[test]
fn op01_sum() {
    assert_eq!(params("N1 R33=128. R24=-8. G26 R5=+01332445")[45], 120_000);
}

#[test]
fn op02_subtraction() {
    assert_eq!(params("N1 R47=2 R1=1 G26 R5=+02470147")[47], 1);
}

#[test]
fn op04_division_decimal_and_raw() {
    assert_eq!(params("N1 R26=1.5 R3=+2.000 G26 R5=+04260337")[37], 750);
    assert_eq!(params("N1 R1=7 R2=2 G26 R5=-04010203")[3], 3);
}

#[test]
fn op04_division_by_zero_is_a_run_time_error() {
    let (prog, _) =
        partprogram::compile(&mill(), "t", "%1\nN1 R1=7 R2=0 G26 R5=04010203\nN2 M30\n");
    let prog = prog.expect("compiles");
    for backend in [Backend::Native, Backend::Interpreter] {
        let err = partprogram::plan(
            &prog,
            PlanOptions {
                backend,
                ..PlanOptions::default()
            },
        )
        .expect_err("fails");
        assert_eq!(err.1.code, 2500);
        assert!(
            err.1.message.contains("division by zero"),
            "{}",
            err.1.message
        );
    }
}

#[test]
fn op05_square() {
    assert_eq!(params("N1 R1=3. G26 R5=05010002")[2], 9_000);
    assert_eq!(params("N1 R1=3 G26 R5=-05010002")[2], 9);
}

#[test]
fn op06_square_root() {
    assert_eq!(params("N1 R1=2. G26 R5=06010002")[2], 1_414);
}

#[test]
fn op07_absolute_value() {
    assert_eq!(params("N1 R35=-70. G26 R5=+07350040")[40], 70_000);
}

#[test]
fn op08_negation() {
    assert_eq!(params("N1 R10=100. G26 R5=08100010")[10], -100_000);
}

#[test]
fn op09_binary_shift() {
    assert_eq!(params("N1 R46=1.000 R32=-1 G26 R5=+09463242")[42], 500);
    assert_eq!(params("N1 R46=1.000 R32=3 G26 R5=+09463242")[42], 8_000);
}

#[test]
fn op10_reciprocal() {
    assert_eq!(params("N1 R1=4. G26 R5=10010002")[2], 250);
}

#[test]
fn op11_power_of_two() {
    assert_eq!(params("N1 R1=3. G26 R5=11010002")[2], 8_000);
}

#[test]
fn op12_log2() {
    assert_eq!(params("N1 R1=8. G26 R5=12010002")[2], 3_000);
}

#[test]
fn op13_power() {
    assert_eq!(params("N1 R1=2. R2=10. G26 R5=13010203")[3], 1_024_000);
}

#[test]
fn op14_hypotenuse() {
    assert_eq!(params("N1 R1=3. R2=4. G26 R5=14010203")[3], 5_000);
}

#[test]
fn op15_to_19_comparisons_write_73_or_78() {
    assert_eq!(params("N1 R11=116. R30=50. G26 R5=+15113010")[10], 73);
    assert_eq!(params("N1 R11=116. R30=50. G26 R5=+16113010")[10], 73);
    assert_eq!(params("N1 R11=116. R30=50. G26 R5=+17113010")[10], 78);
    assert_eq!(params("N1 R11=116. R30=50. G26 R5=+18113010")[10], 78);
    assert_eq!(params("N1 R27=2 R46=0 G26 R5=+19274610")[10], 78);
    assert_eq!(params("N1 R27=0 R46=0 G26 R5=+19274610")[10], 73);
}

#[test]
fn op20_21_22_conditions_skip_to_endif() {
    let p = params("N1 R1=1 R2=1 R3=5 G28 R5=20010200 R6=41030003 R7=22000000");
    assert_eq!(p[3], 1_005);
    let p = params("N1 R1=1 R2=2 R3=5 G28 R5=20010200 R6=41030003 R7=22000000");
    assert_eq!(p[3], 5);
    let p = params("N1 R1=1 R2=2 R3=5 G28 R5=21010200 R6=41030003 R7=22000000");
    assert_eq!(p[3], 1_005);
}

#[test]
fn op23_24_int_real_conversion() {
    assert_eq!(params("N1 R29=4 G26 R5=23290029")[29], 4_000);
    assert_eq!(params("N1 R29=4.5 G26 R5=24290029")[29], 4);
}

#[test]
fn op25_26_transfer_positions() {
    let p = params("N1 G90 G00 X12.5 Y-3. Z7.\nN2 G27 R5=26010283 R6=25030040");
    assert_eq!((p[33], p[34], p[40]), (12_500, -3_000, 7_000));
}

#[test]
fn op27_tangent_in_degrees() {
    assert_eq!(params("N1 R1=45. G26 R5=27010002")[2], 1_000);
}

#[test]
fn op28_geometric_series() {
    assert_eq!(params("N1 R28=0.8 R39=4.000 G26 R5=+28283940")[40], 2_952);
}

#[test]
fn op29_to_32_conditions() {
    for (op, expect) in [(29, 5), (30, 5), (31, 1_005), (32, 1_005)] {
        let p = params(&format!(
            "N1 R1=1. R2=2. R3=5 G28 R5={op:02}010200 R6=41030003 R7=22000000"
        ));
        assert_eq!(p[3], expect, "op {op}");
    }
}

#[test]
fn op33_runs_a_program_of_control_words() {
    let p = params(
        "N1 R30=-70. R0=0 R2=+15113010 R3=+17113010 R28=4. G26 R5=+33090012 R9=+31300000 R10=+00020003 R11=+08280028 R12=+22000000",
    );
    assert_eq!((p[3], p[28]), (15_113_010, -4_000));
    let p = params(
        "N1 R30=70. R0=0 R2=+15113010 R3=+17113010 R28=4. G26 R5=+33090012 R9=+31300000 R10=+00020003 R11=+08280028 R12=+22000000",
    );
    assert_eq!((p[3], p[28]), (17_113_010, 4_000));
}

#[test]
fn op34_35_move_clear_and_exchange() {
    let p = params("N1 R10=1 R11=2 R12=3 G26 R5=34101220");
    assert_eq!((p[20], p[21], p[22]), (1, 2, 3));
    let p = params("N1 R10=1 R11=2 R12=3 G26 R5=34991110");
    assert_eq!((p[10], p[11], p[12]), (0, 0, 3));
    let p = params("N1 R10=1 R11=2 R20=8 R21=9 G26 R5=35101120");
    assert_eq!((p[10], p[11], p[20], p[21]), (8, 9, 1, 2));
}

#[test]
fn op36_40_43_are_run_time_errors() {
    for op in ["36010203", "40010203", "43010203", "52010203"] {
        let (prog, _) =
            partprogram::compile(&mill(), "t", &format!("%1\nN1 G26 R5={op}\nN2 M30\n"));
        let err =
            partprogram::plan(&prog.expect("compiles"), PlanOptions::default()).expect_err("fails");
        assert_eq!(err.1.code, 2501, "{op}");
    }
}

#[test]
fn op37_38_sine_cosine_times_ten_million() {
    assert_eq!(params("N1 R1=30. G26 R5=37010002")[2], 5_000_000);
    assert_eq!(params("N1 R1=60. G26 R5=38010002")[2], 5_000_000);
}

#[test]
fn op39_arcsine_of_quotient() {
    assert_eq!(params("N1 R1=1. R2=2. G26 R5=39010203")[3], 30_000);
}

#[test]
fn op41_42_increment_decrement_with_immediates() {
    assert_eq!(params("N1 R12=4 G26 R5=-42120212")[12], 2);
    assert_eq!(params("N1 R12=4 G26 R5=+42120212")[12], -1_996);
    assert_eq!(params("N1 R20=0 G26 R5=-41200020")[20], 1);
    assert_eq!(params("N1 R12=2 G26 R5=-41120012")[12], 3);
}

#[test]
fn op44_45_save_and_restore() {
    let p = params("N1 R1=1 R2=2 G26 R5=44000000\nN2 R1=5 R2=6 R3=7 G26 R5=45010203");
    assert_eq!(
        (p[1], p[2], p[3], p[4]),
        (5, 6, 1, 2),
        "saved R1..R2 restored into R3, R4"
    );
}

#[test]
fn op46_47_odd_even() {
    assert_eq!(params("N1 R19=3 G26 R5=+47190017")[17], 78);
    assert_eq!(params("N1 R19=3 G26 R5=+46190017")[17], 73);
    assert_eq!(params("N1 R19=4 G26 R5=+47190017")[17], 73);
}

#[test]
fn op48_decade_logic() {
    assert_eq!(params("N1 R95=0 G26 R5=48110095")[95], 1);
    assert_eq!(params("N1 R95=11 G26 R5=48210095")[95], 10);
    assert_eq!(params("N1 R40=100 R41=0 G26 R5=48734041")[41], 73);
}

#[test]
fn op49_50_table_read_and_write() {
    let p = params("N1 M03\nN2 G26 R5=49510220");
    assert_eq!(p[20], 3);
    let p = params("N1 R1=12.5 G27 R5=50210155 R6=49215502");
    assert_eq!(p[2], 12_500);
}

#[test]
fn op51_message_is_recorded() {
    let text = "%1\nN1 R7=42 G26 R5=51050712\nN2 M30\n";
    let plan = run(&mill(), text, PlanOptions::default());
    assert_eq!(plan.messages.len(), 1);
    assert_eq!(
        (
            plan.messages[0].code,
            plan.messages[0].value,
            plan.messages[0].mode
        ),
        (5, 42, 2)
    );
}

#[test]
fn double_precision_product_and_division() {
    let p = params("N1 R29=1.678 R40=70. R39=4. G27 R5=+03294090 R6=+04903940");
    assert_eq!(p[40], 29_365);
    let p = params("N1 R30=-70. R31=-100. G26 R5=+00800085");
    assert_eq!((p[35], p[36]), (-70_000, -100_000));
}
