%
O2023 (R=50 ON A CIRCLE)
(Negrau, Pancu and Grebenisan 2023, seed 002, Table 3: a cylinder of radius 50 mm with a wall)
(thickening from 0 to 180 degrees and back, printed on the TMA-AL-550 hybrid machining centre)
(with a constant filament feed: M23/M24 start and stop the feed, M27/M28 the heating.)
(The axis feed F rises by 5 mm/min every 2 degrees from 100 at 180 degrees, so the slow side)
(gets the wide bead, A = Q / v. As printed in the paper M02 came before M24 and M28, which)
(would end the program first: here they come before M30. Text as tests/gcode/macro_test.cpp.)
N5 T2 M06 (PRINT HEAD CALL)
N6 G0 G54 G90 G80 G18 (WORK SYSTEM SETTING, WORK PLAN, ABSOLUTE PROGRAMMING)
N10 #1=0.5 (START [Z])
N20 #2=20 (END [Z])
N30 #3=0.5 (INCREMENT ON [Z])
N40 WHILE [#1LE#2] DO 2
(UPPER SEMICIRCLE)
N50 #10=50 (RADIUS OF SEMICIRCLE)
N60 #11=180 (STARTING ANGLE)
N70 #12=0 (END ANGLE)
N80 #13=2 (ANGULAR INCREMENT)
N90 #17=100 (STARTING FEED)
N100 #18=5 (FEED INCREMENT)
N110 G0 G18 X-50 Y0 M27 (START HEATING)
N120 G1 Z#1 F1000 M23 (FILAMENT FEED START)
N130 WHILE [#11GE#12] DO 1
N140 #15=#10*COS[#11]
N150 #16=#10*SIN[#11]
N160 G1 X#15 Y#16 F#17
N170 #11=#11-#13
N180 #17=#17+#18
N190 END 1
(LOWER HALF CIRCLE)
N200 #10=50 (RADIUS OF SEMICIRCLE)
N210 #11=0 (STARTING ANGLE)
N220 #12=180 (END ANGLE)
N230 #13=2 (ANGULAR INCREMENT)
N240 #18=5 (FEED INCREMENT)
N250 G0 G18 X50 Y0
N260 G1 Z#1 F1000
N270 WHILE [#11LE#12] DO 1
N280 #15=#10*COS[#11]
N290 #16=-#10*SIN[#11]
N300 G1 X#15 Y#16 F#17
N310 #11=#11+#13
N320 #17=#17-#18
N330 END 1
N340 #1=#1+#3
N350 END 2
N360 M24 (FILAMENT FEED STOP)
N370 M28 (HEATING OFF)
N380 M30
%
