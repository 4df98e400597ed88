/* sim_trace.c: what a run shows: its trace rows (CSV), the metrics at the end and their JSON. */
#include <string.h>
#include "sim.h"
#include "hal_host.h"
#include "params.h"
#include "app.h"
#include "ctl.h"

void sim_row(const sim_t *sim, sim_row_t *r)
{
    const plant_t *pl = &sim->plant;
    memset(r, 0, sizeof *r);
    r->t_s = sim->t_ns * 1e-9;
    r->v_cmd_kmh = pl->v_cmd_kmh;
    r->v_true_kmh = plant_speed_kmh(pl);
    r->v_meas_kmh = app_status.in.speed_kmh_x100 / 100.0;
    r->target_lpm = app_status.in.target_lpm_x100 / 100.0;
    r->flow_meas_lpm = app_status.in.flow_lpm_x100 / 100.0;
    r->flow_true_lpm = sim->flow_true_lpm;
    r->boom_lpm = sim->boom_lpm;
    r->pump_lpm = pl->q_pump;
    r->bypass_lpm = pl->q_bypass;
    r->relief_lpm = pl->q_relief;
    r->p_bar = pl->p_bar;
    r->p_meas_kpa = app_status.in.pressure_kpa;
    r->adc_pressure = hal_host_io.adc[HAL_ADC_PRESSURE];
    r->adc_level = hal_host_io.adc[HAL_ADC_LEVEL];
    r->valve_pos = pl->theta;
    r->valve_drive = pl->drive;
    r->ctl_drive = app_status.drive / 32768.0;
    r->kp = ctl_gain(0) / 4096.0;
    r->ki = ctl_gain(1) / 4096.0;
    r->kd = ctl_gain(2) / 4096.0;
    r->tank_l = pl->tank_v;
    r->tank_meas_l = app_status.tank_l;
    r->pto_rpm = pl->pto_now_rpm;
    r->spray_on = hal_host_io.spray_on;
    r->open_nozzles = pl->open_nozzles;
    r->sections = hal_host_io.sections;
    r->alarms = app_status.alarms;
    r->ref_lpm = sim_reference_lpm(sim);
    r->rate_l_ha = sim->set_rate;
    r->width_m = pl->open_nozzles * pl->p.spacing_m;
}

void sim_csv_header(FILE *f)
{
    fputs("t_s,v_cmd_kmh,v_true_kmh,v_meas_kmh,target_lpm,flow_meas_lpm,flow_true_lpm,boom_lpm,"
          "pump_lpm,bypass_lpm,relief_lpm,p_bar,p_meas_kpa,adc_pressure,adc_level,valve_pos,valve_drive,"
          "ctl_drive,kp,ki,kd,tank_l,tank_meas_l,pto_rpm,spray_on,open_nozzles,sections,alarms,ref_lpm,rate_l_ha,"
          "width_m\n", f);
}

void sim_csv_row(FILE *f, const sim_row_t *r)
{
    fprintf(f, "%.3f,%.4f,%.4f,%.2f,%.2f,%.2f,%.4f,%.4f,%.3f,%.3f,%.3f,%.4f,%.0f,%d,%d,%.5f,%.4f,"
               "%.5f,%.4f,%.4f,%.4f,%.3f,%.0f,%.1f,%d,%d,%d,0x%04x,%.4f,%.0f,%.3f\n",
            r->t_s, r->v_cmd_kmh, r->v_true_kmh, r->v_meas_kmh, r->target_lpm, r->flow_meas_lpm,
            r->flow_true_lpm, r->boom_lpm, r->pump_lpm, r->bypass_lpm, r->relief_lpm, r->p_bar,
            r->p_meas_kpa, r->adc_pressure, r->adc_level, r->valve_pos, r->valve_drive, r->ctl_drive,
            r->kp, r->ki, r->kd, r->tank_l, r->tank_meas_l, r->pto_rpm, r->spray_on, r->open_nozzles,
            r->sections, r->alarms, r->ref_lpm, r->rate_l_ha, r->width_m);
}

void sim_trace_csv(sim_t *sim, FILE *f, double period_s)
{
    sim->csv = f;
    if (!f)
        return;
    sim->csv_period_ns = (uint64_t)((period_s > 0.001 ? period_s : 0.001) * 1e9 + 0.5);
    sim->next_csv_ns = sim->t_ns + sim->csv_period_ns;
    sim_csv_header(f);
}

void sim_finish(sim_t *sim, metrics_result_t *r)
{
    metrics_finish(&sim->metrics, r);
}

void sim_json(const sim_t *sim, const metrics_result_t *r, FILE *f)
{
    char extra[512];
    const char *name = sim->scn->name;
    char clean[256];
    size_t i, k = 0;
    for (i = 0; name[i] && k + 2 < sizeof clean; i++) {
        if (name[i] == '"' || name[i] == '\\')
            clean[k++] = '\\';
        clean[k++] = (char)((unsigned char)name[i] < 32 ? '?' : name[i]);
    }
    clean[k] = 0;
    snprintf(extra, sizeof extra, "\"scenario\":\"%s\",\"controller\":\"%s\",\"seed\":%llu,",
             clean, ctl_name((uint8_t)param_v[P_CONTROLLER]), (unsigned long long)sim->scn->seed);
    metrics_json(f, &sim->metrics, r, extra, sim->wall_s, sim->cpu_s);
}
