/* The iMAX B6's power stage, battery and sensors as physics, with no simulator in it: the simavr harness
 * (b6_sim.c) feeds it what the firmware's pins do and asks it what the ADC's inputs see. Wiring and
 * full scales come from b6_board.h; component values the cheali sources do not give are marked as assumed. */
#ifndef B6_MODEL_H
#define B6_MODEL_H

#include <stdint.h>
#include "b6_board.h"

#define B6_MAX_CELLS 6

typedef enum {
    B6_FAULT_DISCONNECT, B6_FAULT_REVERSE, B6_FAULT_CELL_HIGH, B6_FAULT_SENSOR_OPEN, B6_FAULT_SINK_HOT,
    B6_FAULT_INPUT_LOW, B6_FAULT_HANG, B6_FAULT_SLOW_LOOP, B6_FAULT_INPUT_SAG, B6_FAULT_KINDS
} b6_fault_t;

extern const char *const b6_fault_names[B6_FAULT_KINDS];

/* What the firmware's pins set, sampled by the harness. */
typedef struct {
    double buck_duty, boost_duty;   /* 0..1, the switches' on-time */
    double discharge_duty;          /* 0..1 of OC1A while the discharger is enabled */
    int smps_on, output_on, discharge_on;
    unsigned balancer;              /* bit n-1: cell n's bleed resistor switched on */
} b6_drive_t;

typedef struct {
    /* tolerances drawn from the seed */
    double aref_v;
    double gain[B6_Q_NONE];         /* actual full scale / nominal, per quantity */
    double ismps_zero_adc16, idis_zero_adc16;
    double inductor_h, vin_v;
    /* the pack */
    int cells;
    int no_lead;                    /* the balance lead unplugged: every tap reads 0 (a pack on its main leads only) */
    double soc[B6_MAX_CELLS], capacity_as[B6_MAX_CELLS], r_cell[B6_MAX_CELLS];
    /* state */
    double il_a, vc_v, i_batt_a, v_term_v, i_dis_a, t_sink_c, t_pack_c;
    b6_drive_t drive;
    int fault[B6_FAULT_KINDS];
    uint64_t rng;
} b6_model_t;

/* A pack of `cells` lithium-polymer cells at `soc`, `spread_mv` apart from the lowest to the highest,
 * `capacity_mah` each; component tolerances from `seed`. */
void b6_model_init(b6_model_t *m, uint64_t seed, int cells, double capacity_mah, double soc, double spread_mv);
/* Advance the physics by dt seconds with the drive last set. */
void b6_model_step(b6_model_t *m, double dt);
/* The value (V, A or degC) input `q` carries at the board's terminals, faults applied. */
double b6_model_quantity(const b6_model_t *m, b6_quantity_t q);
/* The voltage at the ADC pin for input `in` (its divider's tolerance applied), plus noise. */
double b6_model_pin_v(b6_model_t *m, const b6_input_t *in);
/* A true cell voltage (at its terminals), 0-based. */
double b6_model_cell_v(const b6_model_t *m, int k);
/* ADC16 (65536 = AREF) the input reads for `value` on this board: what a calibration against meters finds. */
double b6_model_adc16(const b6_model_t *m, const b6_input_t *in, double value);
/* 1 when the stage can drive current into or out of the battery (the trace's output_enabled). */
int b6_model_output_enabled(const b6_model_t *m);

#endif
