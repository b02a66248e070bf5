%
O1000 (every statement once)
#1 = 10.0
#2 = [#1 * 2 + 1] MOD 7
#3 = SIN[30] + COS[60] + TAN[45] + ASIN[0.5] + ACOS[0.5] + ATAN[1]/[1] + ATAN[1, 1]
#4 = SQRT[16] + ABS[-2] + ROUND[2.5] + FIX[2.7] + FUP[2.2] + LN[2] + EXP[1] + POW[2, 3]
#[100 + 1] = #1
IF [#1 EQ #0] GOTO 90
IF [#1 GT 5] THEN #5 = 1
#6 = [#1 GE 5] AND [#1 LE 20] OR [#1 NE 3] XOR 0
WHILE [#5 LT 4] DO 1
  G1 X#5 Y-#5 Z[#5 * 0.5] F1200
  #5 = #5 + 1
END 1
M98 P2000 L2
/ G1 X99
N90 G0 Z10 (done)
M30
O2000
G1 X#101 Y0
M99
%
