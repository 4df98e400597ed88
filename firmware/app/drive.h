/* drive.h: the valve's drive each period (drive.c): start-up closing, controller, shut boom, over-pressure, jogs. */
#ifndef DRIVE_H
#define DRIVE_H

#include "compiler.h"

void drive_init(void);
/* The boom opened (spraying starts): the start-up closing if due, the controller from rest. */
void drive_spray_on(uint8_t manual);
/* This period's drive to the valve (valve_set), and what it got back to the controller. */
void drive_step(void);
/* The pressure above P max (the sensor working). */
uint8_t drive_overp(void);
/* Periods of start-up closing left (0: the controller drives). */
uint8_t drive_priming(void);
/* 1: the boom is shut and the bypass at its open stop or held at the spraying pressure. */
uint8_t drive_parked(void);

#endif
