O1000 (bolt circle via G65)
G21 G17 G90 G54
G00 Z10.
G65 P9010 X50. Y20. R30. A0 B90. K4 Z-5.
G00 Z10.
M30
O9010 (bolt circle: X Y centre, R radius, A start angle, B step, K count, Z depth)
#10 = 1
WHILE [#10 LE #6] DO1
#11 = #1 + [#10 - 1] * #2
G00 X[#24 + #18 * COS[#11]] Y[#25 + #18 * SIN[#11]]
G01 Z#26 F100.
G00 Z2.
#10 = #10 + 1
END1
M99
