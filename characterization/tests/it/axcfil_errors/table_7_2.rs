//! Table 7.2 of the manual: the AXCFIL checks (codes 101–228).

use super::*;

case!(
    e101_tick_too_big,
    BASE,
    [("TIM=1,", "TIM=64,")],
    101,
    [("64", 0)],
    []
);
case!(
    e102_cpu_missing,
    BASE,
    [("CAS=1,", "CAS=,")],
    102,
    [("CAS", 0)],
    []
);
case!(
    e103_cas_cpu,
    BASE,
    [("CAS=1,", "CAS=2,")],
    103,
    [("CAS=^2", 0)],
    []
);
case!(
    e104_servo_tick,
    BASE,
    [("CAS=1,XZS,2", "CAS=1,XZS,0")],
    104,
    [("XZS,^0", 0)],
    []
);
case!(
    e105_interpolator_cpu,
    BASE,
    [("IN1=1,", "IN1=2,")],
    105,
    [("IN1=^2", 0)],
    []
);
case!(
    e106_elements,
    BASE,
    [("S,2,16", "S,2,65")],
    106,
    [("65", 0)],
    []
);
case!(
    e107_interpolator_tick,
    BASE,
    [("S,2,16", "S,64,16")],
    107,
    [("64", 0)],
    []
);
case!(
    e108_one_spindle,
    BASE,
    [("IN1=1,XZ,S,", "IN1=1,XZ,SQ,")],
    108,
    [("SQ", 0)],
    []
);
case!(
    e109_no_axes,
    BASE,
    [("CAS=1", "IN2=1,,,2,1\nCAS=1")],
    109,
    [("IN2", 0)],
    []
);
case!(
    e110_interpolator_table,
    BASE,
    [(
        "CAS=1",
        "IN2=1,,,2,1\nIN3=1,,,2,1\nIN4=1,,,2,1\nIN5=1,,,2,1\nIN6=1,,,2,1\nIN7=1,,,2,1\nIN8=1,,,2,1\nIN9=1,,,2,1\nINA=1,,,2,1\nCAS=1"
    )],
    110,
    [("INA", 0)],
    [109]
);
case!(
    e111_duplicate_interpolator,
    BASE,
    [("CAS=1", "IN1=1,,,2,1\nCAS=1")],
    111,
    [("IN1", 1)],
    [109]
);
case!(
    e112_cas_empty,
    BASE,
    [("CAS=1,XZS,2", "CAS=1,,2")],
    112,
    [("CAS", 0)],
    [119, 149]
);
case!(
    e113_cas_duplicate,
    BASE,
    [("CAS=1,XZS,2", "CAS=1,XZSX,2")],
    113,
    [("XZS^X", 0)],
    []
);
case!(
    e114_axis_table,
    BASE,
    [
        ("NBP=1,", "NBP=3,"),
        (
            "*2",
            "PRO=2\nCAS=1,ABCDEFGHIJ,2\nPRO=3\nCAS=1,ABCDEFGHIJ,2\n*2"
        )
    ],
    114,
    [("*1", 0)],
    [169, 922]
);
case!(
    e115_interpolator_axes,
    BASE,
    [("IN1=1,XZ,", "IN1=1,XZABCDEFG,")],
    115,
    [("XZABCDEFG", 0)],
    [119]
);
case!(
    e116_several_interpolators,
    BASE,
    [("CAS=1", "IN2=1,X,,2,1\nCAS=1")],
    116,
    [("IN2", 0)],
    []
);
case!(
    e118_second_cas,
    BASE,
    [("*2", "CAS=1,XZS,2\n*2")],
    118,
    [("CAS", 1)],
    []
);
case!(
    e119_not_in_cas,
    BASE,
    [("IN1=1,XZ,", "IN1=1,XZQ,")],
    119,
    [("IN1", 0)],
    []
);
case!(
    e120_int_tick_servo,
    BASE,
    [("S,2,16", "S,3,16")],
    120,
    [("IN1", 0)],
    []
);
case!(
    e121_tim_missing,
    BASE,
    [("TIM=1,0,0,0,0\n", "")],
    121,
    [("*1", 0)],
    []
);
case!(
    e124_tick_zero,
    BASE,
    [("TIM=1,", "TIM=0,")],
    124,
    [("TIM=^0", 0)],
    []
);
case!(
    e127_servo_tick_cpu,
    BASE,
    [
        ("TIM=1,", "TIM=2,"),
        ("XZS,2", "XZS,3"),
        ("S,2,16", "S,6,16")
    ],
    127,
    [("CAS", 0)],
    []
);
case!(
    e128_int_tick_cpu,
    BASE,
    [("TIM=1,", "TIM=2,"), ("S,2,16", "S,3,16")],
    128,
    [("IN1", 0)],
    []
);
case!(
    e131_duplicate,
    BASE,
    [("GM0=10000", "RAP=1,1\nGM0=10000")],
    131,
    [("RAP", 1)],
    []
);
case!(
    e132_tpa_missing,
    BASE,
    [("TPA=41,\n", "")],
    132,
    [("NAS=X", 0)],
    []
);
case!(
    e133_ntc_missing,
    BASE,
    [("NTC=1,1\n", "")],
    133,
    [("NAS=X", 0)],
    []
);
case!(
    e134_gas_missing,
    BASE,
    [("GAS=0.004,0.002,,\n", "")],
    134,
    [("NAS=X", 0)],
    []
);
case!(
    e135_pas_missing,
    BASE,
    [("PAS=5000,5,,\n", "")],
    135,
    [("NAS=X", 0)],
    []
);
case!(
    e137_rap_missing,
    BASE,
    [("RAP=10000,800\n", "")],
    137,
    [("NAS=X", 0)],
    []
);
case!(
    e138_man_missing,
    BASE,
    [("MAN=2000,200\nGM0=10000", "GM0=10000")],
    138,
    [("NAS=X", 0)],
    []
);
case!(
    e139_man_speed,
    BASE,
    [("MAN=2000,200", "MAN=20000,200")],
    139,
    [("MAN", 0)],
    []
);
case!(
    e140_man_accel,
    BASE,
    [("MAN=2000,200", "MAN=2000,2000")],
    140,
    [("MAN", 0)],
    []
);
case!(
    e141_pos_missing,
    BASE,
    [("POS=.005,2\n", "")],
    141,
    [("NAS=X", 0)],
    []
);
case!(
    e142_srv_missing,
    BASE,
    [("SRV=.5,2,10\n", "")],
    142,
    [("NAS=X", 0)],
    []
);
case!(
    e147_gm0_on_spindle,
    BASE,
    [("GM1=", "GM0=3000,8.5,6,,\nGM1=")],
    147,
    [("GM0", 2)],
    []
);
case!(
    e148_gm1_missing,
    BASE,
    [("GM1=3000,8.5,6,,\n", "")],
    148,
    [("NAS=S", 0)],
    []
);
case!(
    e149_nas_undeclared,
    BASE,
    [("*3", "NAS=Q\nTPA=1,\nNTC=0,0\n*3")],
    149,
    [("NAS=^Q", 0)],
    []
);
case!(
    e150_gm_not_zero,
    BASE,
    [("GM0=10000", "GM1=10000")],
    150,
    [("GM1", 0)],
    []
);
case!(
    e151_no_nas,
    BASE,
    [("PRO=1\nNAS=X", "PRO=1\nAFC=1\nNAS=X")],
    151,
    [("AFC", 0)],
    []
);
case!(
    e152_no_interpolator,
    BASE,
    [
        ("CAS=1,XZS,2", "CAS=1,XZSQ,2"),
        (
            "*3",
            "NAS=Q\nTPA=1,\nNTC=4,\nPAS=400,1,,\nGAS=,\nPOS=.01,2\nSRV=,,\n*3"
        )
    ],
    152,
    [("POS=.01", 0)],
    []
);
case!(
    e153_el_pitch_zero,
    BASE,
    [("PAS=5000,5,,", "PAS=0,5,,")],
    153,
    [("PAS=^0", 0)],
    []
);
case!(
    e154_mec_pitch_zero,
    BASE,
    [("PAS=5000,5,,", "PAS=5000,0,,")],
    154,
    [("5000,^0", 0)],
    []
);
case!(
    e155_spindle_type,
    BASE,
    [("TPA=820,", "TPA=801,")],
    155,
    [("TPA=801", 0)],
    [137, 138, 150, 181, 188]
);
case!(
    e157_coordinate_ptp,
    BASE,
    [("TPA=41,", "TPA=43,")],
    157,
    [("TPA=43", 0)],
    [931, 938]
);
case!(
    e158_switch_name,
    BASE,
    [("TPA=41,", "TPA=49,YZ")],
    158,
    [("TPA=49", 0)],
    []
);
case!(
    e159_switch_undeclared,
    BASE,
    [("TPA=41,", "TPA=49,Q")],
    159,
    [("TPA=49", 0)],
    []
);
case!(
    e160_transducer,
    BASE,
    [("NTC=1,1", "NTC=17,1")],
    160,
    [("17", 0)],
    []
);
case!(
    e161_converter,
    BASE,
    [("NTC=1,1", "NTC=1,17")],
    161,
    [("NTC=1,^17", 0)],
    []
);
case!(
    e163_direction,
    BASE,
    [("POS=.005,2", "MCZ=I0A8,2,200\nPOS=.005,2")],
    163,
    [("I0A8,^2", 0)],
    []
);
case!(
    e166_asm_name,
    BASE,
    [("POM=0.5", "ASM=XY\nPOM=0.5")],
    166,
    [("ASM=^XY", 0)],
    []
);
case!(
    e167_asm_undeclared,
    BASE,
    [("POM=0.5", "ASM=Q\nPOM=0.5")],
    167,
    [("ASM", 0)],
    []
);
case!(
    e168_switch_mismatch,
    BASE,
    [("TPA=41,", "TPA=49,Z")],
    168,
    [("TPA=49", 0)],
    []
);
case!(
    e169_axis_not_defined,
    BASE,
    [("CAS=1,XZS,2", "CAS=1,XZSQ,2")],
    169,
    [("*2", 0)],
    []
);
case!(
    e172_gm_range,
    BASE,
    [("GM0=10000", "GM100=1,1,1\nGM0=10000")],
    172,
    [("GM100", 0)],
    []
);
case!(
    e173_s3_no_nas,
    BASE,
    [("*3\n", "*3\nPRO=1\nE001=0\n")],
    173,
    [("E001", 0)],
    []
);
case!(
    e174_s3_order,
    BASE,
    [(
        "*3\n",
        "*3\nPRO=1\nNAS=Z\nPAS=50\nE002=0\nE001=0.002\nE003=0\nNM0=E002\n"
    )],
    174,
    [("E001", 0)],
    []
);
case!(
    e175_s3_too_few,
    BASE,
    [("*3\n", "*3\nPRO=1\nNAS=Z\nPAS=50\nE001=0\nNM0=E001\n")],
    175,
    [("NAS=Z", 1)],
    []
);
case!(
    e176_nm0_syntax,
    BASE,
    [(
        "*3\n",
        "*3\nPRO=1\nNAS=Z\nPAS=50\nE001=0\nE002=0.002\nNM0=X5\n"
    )],
    176,
    [("X5", 0)],
    []
);
case!(
    e177_nm0_unknown,
    BASE,
    [(
        "*3\n",
        "*3\nPRO=1\nNAS=Z\nPAS=50\nE001=0\nE002=0.002\nNM0=E009\n"
    )],
    177,
    [("E009", 0)],
    []
);
case!(
    e178_converter_mismatch,
    BASE,
    [("NTC=3,3", "NTC=3,")],
    178,
    [("NTC=3,", 0)],
    []
);
case!(
    e179_spindle_both,
    BASE,
    [("TPA=820,", "TPA=830,")],
    179,
    [("TPA=830", 0)],
    []
);
case!(
    e180_tsm_params,
    BASE,
    [("TSM=4,17", "TSM=4,0")],
    180,
    [("TSM", 0)],
    []
);
case!(
    e181_tsm_not_spindle,
    BASE,
    [("GM0=10000", "TSM=4,17\nGM0=10000")],
    181,
    [("TSM", 0)],
    []
);
case!(
    e182_before_ntc,
    BASE,
    [
        ("GM1=3000,8.5,6,,\n", ""),
        ("TPA=820,", "TPA=820,\nGM1=3000,8.5,6,,")
    ],
    182,
    [("GM1", 0)],
    []
);
case!(
    e183_nbp_too_many,
    BASE,
    [("NBP=1,", "NBP=6,")],
    183,
    [("NBP=^6", 0)],
    // No follow-on 922 for processes 2..5: the file's one PRO settles the number (issue 12).
    []
);
case!(
    e184_pro_above_nbp,
    BASE,
    [("GM1=3000", "PRO=2\nGM1=3000")],
    184,
    [("PRO=^2", 0)],
    [148, 151, 189, 932]
);
case!(
    e185_no_nbp,
    BASE,
    [("NBP=1,ECDF\n", ""), ("*2", "NBP=1,ECDF\n*2")],
    185,
    [("IN1", 0), ("CAS", 0)],
    []
);
case!(
    e187_pro_empty,
    BASE,
    [("*3\n", "*3\nPRO=\n")],
    187,
    [("PRO=\n", 0)],
    []
);
case!(
    e188_pom_not_spindle,
    BASE,
    [("GM0=10000", "POM=0.5,100\nGM0=10000")],
    188,
    [("POM", 0)],
    []
);
case!(
    e189_pom_missing,
    BASE,
    [("POM=0.5,100,0.1,U230K1\n", "")],
    189,
    [("NAS=S", 0)],
    []
);
case!(
    e190_adc_number,
    BASE,
    [("GM0=10000", "ADP=9,5,1,2\nGM0=10000")],
    190,
    [("ADP=^9", 0)],
    []
);
case!(
    e191_adp_zero,
    BASE,
    [("GM0=10000", "ADP=1,0,1,2\nGM0=10000")],
    191,
    [("ADP=1,^0", 0)],
    []
);
case!(
    e193_skw_not_slave,
    BASE,
    [("POM=0.5", "SKW=X,1,0,0\nPOM=0.5")],
    193,
    [("SKW", 0)],
    []
);
case!(
    e194_skw_name,
    &slave(),
    [("SKW=X,", "SKW=XZ,")],
    194,
    [("SKW", 0)],
    []
);
case!(
    e195_skw_undeclared,
    &slave(),
    [("SKW=X,", "SKW=R,")],
    195,
    [("SKW", 0)],
    []
);
case!(
    e196_master_twice,
    &slave(),
    [
        ("CAS=1,XZSQ,2", "CAS=1,XZSQR,2"),
        ("*3", "NAS=R\nTPA=1001,\nNTC=5,5\nGAS=,,,\nSKW=X,1,0,0\n*3")
    ],
    196,
    [("SKW", 1)],
    []
);
case!(
    e197_slave_twice,
    &slave(),
    [
        ("CAS=1,XZSQ,2", "CAS=1,XZSQR,2"),
        ("*3", "NAS=R\nTPA=1001,\nNTC=5,5\nGAS=,,,\nSKW=Q,1,0,0\n*3")
    ],
    197,
    [("SKW", 0)],
    []
);
case!(
    e198_slave_instructions,
    &slave(),
    [("SKW=X,", "POS=.01,1\nSKW=X,")],
    198,
    [("POS=.01", 0)],
    []
);
case!(
    e199_skw_self,
    &slave(),
    [("SKW=X,", "SKW=Q,")],
    199,
    [("SKW", 0)],
    []
);
case!(
    e200_slave_interpolated,
    &slave(),
    [
        ("IN1=1,XZ,", "IN1=1,XZQ,"),
        ("CAS=1,XZSQ,2", "CAS=1,XZQS,2")
    ],
    200,
    [("NAS=Q", 0)],
    [928]
);
case!(
    e201_slave_before_master,
    &slave(),
    [
        ("CAS=1,XZSQ,2", "CAS=1,QXZS,2"),
        (
            "NAS=Q\nTPA=1001,\nNTC=4,4\nGAS=,,,\nPAS=5000,-5,,\nMCZ=I0A8,0,200\nMFC=I0A9,I0A10\nSKW=X,1,0,0\n",
            ""
        ),
        ("PRO=1\nNAS=X", &format!("PRO=1\n{SLAVE}NAS=X"))
    ],
    201,
    [("SKW", 0)],
    []
);
case!(
    e203_control_point_asm,
    BASE,
    [("TPA=41,", "TPA=C1,")],
    203,
    [("TPA=C1", 0)],
    []
);
case!(
    e204_zone_type,
    BASE,
    [("POM=0.5", "CUB=1,-1,1\nPOM=0.5")],
    204,
    [("CUB", 0)],
    []
);
case!(
    e205_sw_packet_a,
    BASE,
    [("GM0=10000", "SW1=1,-1,I0A5\nGM0=10000")],
    205,
    [("I0A5", 0)],
    []
);
case!(
    e206_acc,
    BASE,
    [("PRO=1\nIN1", "PRO=1\nACC=0,0.5,1,4\nIN1")],
    206,
    [("ACC", 0)],
    []
);
case!(
    e209_before_pas,
    BASE,
    [("PAS=5000,5,,", "MCZ=I0A8,0,200\nPAS=5000,5,,")],
    209,
    [("MCZ", 0)],
    []
);
case!(
    e210_converter_above_200,
    BASE,
    [("NTC=1,1", "NTC=1,201")],
    210,
    [("201", 0)],
    []
);
case!(
    e211_type_not_2,
    BASE,
    [("PAS=5000,5,,", "PAS=5000,5,2,")],
    211,
    [("PAS=5000,5,2", 0)],
    []
);
case!(
    e212_frc_before_gm0,
    BASE,
    [(
        "GM0=10000",
        "FRC=10,50,10,50,100,300,0.95,0,U190K30\nGM0=10000"
    )],
    212,
    [("FRC", 0)],
    []
);
case!(
    e215_zno_signal,
    BASE,
    [("POS=.005,2", "ZNO=0,,100,,0\nPOS=.005,2")],
    215,
    [(",,^100", 0)],
    []
);
case!(
    e216_gra_signal,
    BASE,
    [
        ("TPA=41,", "TPA=80041,"),
        ("GM0=10000", "GRA=I0A3,12\nGM0=10000")
    ],
    216,
    [("I0A3", 0)],
    []
);
case!(
    e217_gra_bits,
    BASE,
    [
        ("TPA=41,", "TPA=80041,"),
        ("GM0=10000", "GRA=I0A8,17\nGM0=10000")
    ],
    217,
    [("17", 0)],
    []
);
case!(
    e218_gra_type,
    BASE,
    [("GM0=10000", "GRA=I0A8,12\nGM0=10000")],
    218,
    [("GRA", 0)],
    []
);
case!(
    e219_hwc_axis,
    BASE,
    [("GM0=10000", "HWC=Q,U140K0\nGM0=10000")],
    219,
    [("HWC", 0)],
    []
);
case!(
    e220_can_number,
    BASE,
    [("CAS=1", "CAN5=1\nCAS=1")],
    220,
    [("CAN5", 0)],
    []
);
case!(
    e221_mcz_kkrm_input,
    BASE,
    [
        ("TPA=41,", "TPA=40041,"),
        ("POS=.005,2", "MCZ=I0A8,0,200,20,0.02\nPOS=.005,2")
    ],
    221,
    [("MCZ", 0)],
    []
);
case!(
    e222_kc_above_10,
    BASE,
    [("GM0=10000,7.5", "GM0=10000,11")],
    222,
    [("11", 0)],
    []
);
case!(
    e224_fopp_not_ptp,
    BASE,
    [("GM0=10000", "FOPP=U222K16\nGM0=10000")],
    224,
    [("FOPP", 0)],
    []
);
case!(
    e225_adg_signals,
    BASE,
    [
        ("TPA=41,", "TPA=8041,"),
        (
            "GM0=10000",
            "ADG=1,0.2,3.8,,U150N0,I150N1,U150N2\nGM0=10000"
        )
    ],
    225,
    [("ADG=1,0.2,3.8,^,", 0)],
    []
);
case!(
    e227_atr_type,
    BASE,
    [("GM0=10000", "ATR=13,0\nGM0=10000")],
    227,
    [("ATR", 0)],
    []
);
case!(
    e228_atr_missing,
    BASE,
    [("TPA=41,", "TPA=200041,")],
    228,
    [("TPA=200041", 0)],
    []
);
