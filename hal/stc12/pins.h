/* pins.h: the pin map of the controller board (STC12C5A60S2, 11.0592 MHz crystal); the README copies it. */
#ifndef PINS_H
#define PINS_H

/*
 *  pin    dir  function
 *  P1.0   in   ADC0  pressure sensor, 4-20 mA across 250 ohm (1-5 V)
 *  P1.1   in   ADC1  tank level sensor, 4-20 mA across 250 ohm
 *  P1.3   in   CCP0  turbine flow meter pulses (PCA module 0, capture on falling edge)
 *  P1.4   out  CCP1  valve H-bridge enable, PCA module 1 PWM, 3.6 kHz
 *  P1.5   out        valve H-bridge IN_A: high = drive the bypass valve open
 *  P1.6   out        valve H-bridge IN_B: high = drive the bypass valve closed
 *  P3.2   in   INT0  wheel Hall sensor (falling edge, time-stamped from the PCA counter)
 *  P3.0   in   RXD   RS232 (MAX232) from the PC
 *  P3.1   out  TXD   RS232 (MAX232) to the PC, 38400 8N1 from the BRT generator
 *  P3.4   out        master boom valve relay (high = spray)
 *  P3.5   out        buzzer (high = sound)
 *  P3.3   out        LCD12864 E / SCLK   (ST7920 serial mode: PSB tied to GND)
 *  P3.6   out        LCD12864 RS / CS
 *  P3.7   out        LCD12864 RW / SID
 *  P2.0-3 out        keypad rows 1-4 (one driven low at a time)
 *  P2.4-7 in         keypad columns 1-4 (pulled up; low = key pressed)
 *  P0.0-7 in         boom section switches 1-8 (to ground when the section is on)
 *
 * Only two PCA modules exist on this chip: module 0 captures the flow meter, module 1 makes
 * the valve PWM, and the wheel sensor (a few pulses a second) is time-stamped from the PCA
 * counter in the INT0 handler, which costs a few microseconds of latency, not resolution.
 */
#define PIN_VALVE_A P1_5
#define PIN_VALVE_B P1_6
#define PIN_SPRAY P3_4
#define PIN_BUZZER P3_5
#define PIN_LCD_SCLK P3_3
#define PIN_LCD_CS P3_6
#define PIN_LCD_SID P3_7
#define PORT_KEYPAD P2
#define PORT_SECTIONS P0
#define ADC_PINS_MASK 0x03   /* P1ASF: P1.0 and P1.1 are analog */

#endif
