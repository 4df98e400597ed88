/* stc12_hw.cc: the STC12C5A60S2's peripherals in uCsim's s51 as the datasheet gives them: ports and their modes, PCA, ADC, UART 1 on the BRT, IAP EEPROM, watchdog, reset values, and their time (advance). */
/* This file is part of the sprayer project's patch to uCsim (GPL v2 or later, as uCsim). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "regs51.h"
#include "portcl.h"
#include "interruptcl.h"
#include "stc12cl.h"
#include "stc12_link.h"

/* ---- the peripherals -------------------------------------------------------------------- */
#define AUXR_A 0x8e
#define P1M1_A 0x91
#define P1M0_A 0x92
#define P3M1_A 0xb1
#define P3M0_A 0xb2
#define BRT_A 0x9c
#define ADC_CONTR_A 0xbc
#define ADC_RES_A 0xbd
#define ADC_RESL_A 0xbe
#define WDT_CONTR_A 0xc1
#define IAP_DATA_A 0xc2
#define IAP_ADDRH_A 0xc3
#define IAP_ADDRL_A 0xc4
#define IAP_CMD_A 0xc5
#define IAP_TRIG_A 0xc6
#define IAP_CONTR_A 0xc7
#define CCON_A 0xd8
#define CMOD_A 0xd9
#define CCAPM0_A 0xda
#define CL_A 0xe9
#define CH_A 0xf9
#define CCAP0L_A 0xea
#define CCAP0H_A 0xfa
#define PCA_PWM0_A 0xf2


cl_stc12hw::cl_stc12hw(class cl_uc *auc):
  cl_hw(auc, HW_DUMMY, 1, "stc12")
{
  fin= fout= NULL;
  ev= NULL;
  n_ev= i_ev= cap_ev= 0;
  memset(eeprom, 0xff, sizeof eeprom);
  memset(vec, 0, sizeof vec);
  memset(adc_in, 0, sizeof adc_in);
  now= 0;
  slot_end= 0;
  pass_pc= 0xffffffff;
  n_watch= 0;
  quit= false;
  cause= 0;
  rx_byte= 0;
  rx_ok= 0;
  hung= pin_reset= sweep= false;
  sweep_at= 0;
  sweep_off= sweep_k= 0;
  early= 0;
  sp_max= 0;
  p2_latch= 0xff;
}

int
cl_stc12hw::init(void)
{
  cl_hw::init();
  sfr= uc->address_space(MEM_SFR_ID);
  xram= uc->address_space(MEM_XRAM_ID);
  c_ccon= sfr->get_cell(CCON_A);
  c_cmod= sfr->get_cell(CMOD_A);
  c_cl= sfr->get_cell(CL_A);
  c_ch= sfr->get_cell(CH_A);
  for (int i= 0; i < 2; i++)
    {
      c_ccapm[i]= sfr->get_cell(CCAPM0_A + i);
      c_ccapl[i]= sfr->get_cell(CCAP0L_A + i);
      c_ccaph[i]= sfr->get_cell(CCAP0H_A + i);
      c_pwm[i]= sfr->get_cell(PCA_PWM0_A + i);
    }
  c_adc= register_cell(sfr, ADC_CONTR_A);
  c_res= sfr->get_cell(ADC_RES_A);
  c_resl= sfr->get_cell(ADC_RESL_A);
  c_scon= sfr->get_cell(SCON);
  c_sbuf= register_cell(sfr, SBUF);
  c_brt= sfr->get_cell(BRT_A);
  c_auxr= sfr->get_cell(AUXR_A);
  c_wdt= register_cell(sfr, WDT_CONTR_A);
  c_pcon= sfr->get_cell(PCON);
  c_iap_data= sfr->get_cell(IAP_DATA_A);
  c_iap_ah= sfr->get_cell(IAP_ADDRH_A);
  c_iap_al= sfr->get_cell(IAP_ADDRL_A);
  c_iap_cmd= sfr->get_cell(IAP_CMD_A);
  c_iap_trig= register_cell(sfr, IAP_TRIG_A);
  c_iap_contr= sfr->get_cell(IAP_CONTR_A);
  c_p1= sfr->get_cell(P1);
  c_p2= sfr->get_cell(P2);
  c_p3= sfr->get_cell(P3);
  c_p1m0= sfr->get_cell(P1M0_A);
  c_p1m1= sfr->get_cell(P1M1_A);
  c_p3m0= sfr->get_cell(P3M0_A);
  c_p3m1= sfr->get_cell(P3M1_A);
  c_th1= sfr->get_cell(TH1);
  c_sp= sfr->get_cell(SP);
  c_tmod= sfr->get_cell(TMOD);
  for (int i= 0; i < 4; i++)
    port[i]= uc->get_hw(HW_PORT, i, NULL);
  const char *in= getenv("STC12_LINK_IN"), *out= getenv("STC12_LINK_OUT");
  if (in && out)
    {
      fin= fopen(in, "rb");
      fout= fin ? fopen(out, "wb") : NULL;
      if (!fin || !fout)
        {
          fprintf(stderr, "stc12: cannot open the link %s, %s\n", in, out);
          exit(2);
        }
    }
  const char *prof= getenv("STC12_PROFILE");
  prof_out= prof ? fopen(prof, "w") : NULL;
  prof_cur= prof_keep[0]= prof_keep[1]= prof_keep[2]= prof_keep[3]= NULL;
  const char *at= getenv("STC12_PROFILE_AT");
  prof_at= at ? strtol(at, NULL, 0) : -1;
  prof_hit= false;
  prof_n= prof_cap= 0;
  memset(prof_keep_n, 0, sizeof prof_keep_n);
  memset(prof_keep_len, 0, sizeof prof_keep_len);
  stall= 0;
  reset_due= false;
  resets= 0;
  isr_depth= 0;
  passes= 0;
  pass_start= 0;
  pass_max= pass_sum= step_max= 0;
  pass_adc= pass_iap= max_adc= max_iap= 0;
  n_tx= 0;
  keys= 0;
  powered= false;               /* the first reset is the power-on's: POF and LVDF set */
  chip_reset(0);
  return 0;
}

/* The reset values (datasheet, "Special function registers": every port latch 1, every pin
 * quasi-bidirectional, PxM0 = PxM1 = 0; AUXR 0: timers at SYSCLK/12, the on-chip XRAM on;
 * WDT_CONTR 0 but WDT_FLAG after a watchdog reset; PCON's POF and LVDF kept). */
void
cl_stc12hw::chip_reset(t_mem pcon_before)
{
  uint8_t pcon_flags= powered ? (uint8_t)(pcon_before & 0x30) : 0x30;
  powered= true;
  uint8_t wdt_flag= reset_due ? 0x80 : 0;
  if (reset_due || pin_reset)
    {
      resets++;
      cause= wdt_flag;
    }
  reset_due= false;
  pin_reset= false;
  hung= false;
  stall= 0;
  isr_depth= 0;
  pass_start= 0;
  c_pcon->set(pcon_flags);
  c_wdt->set(wdt_flag);
  c_iap_ah->set(0);
  c_iap_al->set(0);
  pca_sub= 0;
  ccp0_prev= 1;
  adc_done= tx_done= rx_at= 0;
  wdt_count= 0;
  iap_seq= 0;
  p1_high_at= p3_high_at= 0;
  keypad();
}

void
cl_stc12hw::added_to_uc(void)
{
  class cl_it_src *is;
  class cl_address_space *sfr= uc->address_space(MEM_SFR_ID);
  /* UART 1 (vector 0x23, ES, PS), its two flags as two sources */
  uc->it_sources->add(is= new cl_it_src(uc, bmES, sfr->get_cell(IE), bmES, sfr->get_cell(SCON), bmRI,
                                        0x23, false, false, "uart RI", 4));
  is->init();
  uc->it_sources->add(is= new cl_it_src(uc, bmES, sfr->get_cell(IE), bmES, sfr->get_cell(SCON), bmTI,
                                        0x23, false, false, "uart TI", 4));
  is->init();
  /* ADC (0x2B, EADC IE.5, ADC_FLAG) and the low-voltage detector (0x33, ELVD IE.6, LVDF) */
  uc->it_sources->add(is= new cl_it_src(uc, 0x20, sfr->get_cell(IE), 0x20, sfr->get_cell(ADC_CONTR_A), 0x10,
                                        0x2b, false, false, "adc", 5));
  is->init();
  uc->it_sources->add(is= new cl_it_src(uc, 0x40, sfr->get_cell(IE), 0x40, sfr->get_cell(PCON), 0x20,
                                        0x33, false, false, "lvd", 6));
  is->init();
  /* PCA (0x3B, PPCA IP.7): overflow CF with CMOD.ECF, captures CCFn with CCAPMn.ECCFn */
  uc->it_sources->add(is= new cl_stc12_it(uc, sfr->get_cell(CCON_A), 0x80, sfr->get_cell(CMOD_A), 0x01,
                                          0x3b, "pca CF", 0x80));
  is->init();
  uc->it_sources->add(is= new cl_stc12_it(uc, sfr->get_cell(CCON_A), 0x01, sfr->get_cell(CCAPM0_A), 0x01,
                                          0x3b, "pca CCF0", 0x80));
  is->init();
  uc->it_sources->add(is= new cl_stc12_it(uc, sfr->get_cell(CCON_A), 0x02, sfr->get_cell(CCAPM0_A + 1), 0x01,
                                          0x3b, "pca CCF1", 0x80));
  is->init();
}

/* the UART's bit time in clocks: BRT with AUXR.S1BRS (BRTR runs it, BRTx12 at SYSCLK, else
 * SYSCLK/12), else timer 1 in mode 2; PCON.SMOD doubles the rate (datasheet, "Baud rate") */
unsigned
cl_stc12hw::bit_clocks(void)
{
  t_mem auxr= c_auxr->get();
  unsigned ov;
  if (auxr & 0x01)
    {
      if (!(auxr & 0x10))
        return 0;
      ov= (256 - c_brt->get()) * ((auxr & 0x04) ? 1 : 12);
    }
  else
    {
      if ((c_tmod->get() & 0x30) != 0x20)
        return 0;
      ov= (256 - c_th1->get()) * ((auxr & 0x40) ? 1 : 12);
    }
  return (c_pcon->get() & 0x80) ? 16 * ov : 32 * ov;
}

void
cl_stc12hw::uart_tx(uint8_t b)
{
  unsigned bc= bit_clocks();
  int bits= (c_scon->get() & 0x80) ? 10 : 9;     /* mode 3: the 9th bit TB8, a second stop bit at 1 */
  if (n_tx < sizeof tx_log / 12)
    {
      uint8_t *p= tx_log + 12 * n_tx++;
      for (int i= 0; i < 8; i++)
        p[i]= (uint8_t)(now >> (8 * i));
      p[8]= b;
      p[9]= (uint8_t)bc;
      p[10]= (uint8_t)(bc >> 8);
      p[11]= (uint8_t)(bits - ((c_scon->get() & 0x80) && !(c_scon->get() & 0x08) ? 1 : 0));
    }
  tx_done= now + (uint64_t)(1 + bits) * (bc ? bc : 1);
}

/* IAP (datasheet, "IAP/EEPROM"): IAP_CONTR.IAPEN, IAP_CMD 1 read, 2 program, 3 sector erase,
 * started by 0x5A then 0xA5 into IAP_TRIG; the 1 KB EEPROM at IAP addresses 0x0000-0x03FF in
 * 512-byte sectors; an address outside sets CMD_FAIL. The CPU is held for the operation:
 * about 55 us a byte program and 21 ms a sector erase (hal/host/hal_host.h's figures), two
 * clocks a read. */
void
cl_stc12hw::iap(void)
{
  unsigned a= (c_iap_ah->get() << 8) | c_iap_al->get();
  t_mem cmd= c_iap_cmd->get() & 3;
  if (!(c_iap_contr->get() & 0x80) || cmd == 0)
    return;
  if (a >= sizeof eeprom)
    {
      c_iap_contr->set(c_iap_contr->get() | 0x10);
      return;
    }
  if (pass_iap < 255)
    pass_iap++;
  switch (cmd)
    {
    case 1: c_iap_data->set(eeprom[a]); stall= 2; break;
    case 2: eeprom[a]&= (uint8_t)c_iap_data->get(); stall= 608; break;
    case 3: memset(eeprom + (a & ~511u), 0xff, 512); stall= 232243; break;
    }
}

void
cl_stc12hw::write(class cl_memory_cell *cell, t_mem *val)
{
  if (cell == c_sbuf)
    {
      uart_tx((uint8_t)*val);
      *val= rx_byte;            /* SBUF reads the receive buffer */
    }
  else if (cell == c_adc)
    {
      /* ADC_CONTR (datasheet, "ADC"): ADC_POWER 7, SPEED 6-5 (540, 360, 180, 90 clocks),
       * ADC_FLAG 4, ADC_START 3, CHS 2-0; the result 10 bits, ADC_RES the high 8 (ADRJ 0) */
      static const unsigned conv[4]= { 540, 360, 180, 90 };
      if ((*val & 0x88) == 0x88)
        {
          adc_done= now + conv[(*val >> 5) & 3];
          if (pass_adc < 255)
            pass_adc++;
        }
    }
  else if (cell == c_wdt)
    {
      /* WDT_CONTR (datasheet, "Watchdog"): WDT_FLAG 7 (software clears it), EN_WDT 5 (only
       * a reset clears it), CLR_WDT 4 (restarts the count, reads 0), IDLE_WDT 3, PS 2-0 */
      t_mem old= cell->get();
      t_mem v= *val;
      if (v & 0x10)
        wdt_count= 0;
      v= (v & 0x2f) | (old & 0x20) | (old & v & 0x80);
      *val= v;
    }
  else if (cell == c_iap_trig)
    {
      if (*val == 0x5a)
        iap_seq= 1;
      else
        {
          if (*val == 0xa5 && iap_seq)
            iap();
          iap_seq= 0;
        }
    }
}

void
cl_stc12hw::port_pins(int n, t_mem v)
{
  if (port[n])
    port[n]->cfg_write(port_pin, v);
}

/* the keypad's columns (P2.4-7) pulled low by a held key whose row (P2.0-3) is driven low */
void
cl_stc12hw::keypad(void)
{
  uint8_t latch= (uint8_t)c_p2->get(), pins= 0xff;
  for (int r= 0; r < 4; r++)
    if (!(latch & (1 << r)))
      for (int c= 0; c < 4; c++)
        if (keys & (1u << (4 * r + c)))
          pins&= (uint8_t)~(0x10 << c);
  port_pins(2, pins);
}

/* SYSCLK clocks a PCA count by CMOD.CPS (datasheet, "PCA"): /12, /2, timer 0's overflow and
 * ECI not modelled (0), SYSCLK, /4, /6, /8 */
unsigned
cl_stc12hw::pca_clocks(void)
{
  static const unsigned div[8]= { 12, 2, 0, 0, 1, 4, 6, 8 };
  return div[(c_cmod->get() >> 1) & 7];
}

/* Time to `to`: the PCA counter, the watchdog, and whatever completes meanwhile (a
 * conversion, a frame sent or received, a pulse's pin back high), each at its own clock. */
void
cl_stc12hw::advance(uint64_t to)
{
  while (now < to)
    {
      uint64_t t= to;
      if (adc_done && adc_done < t) t= adc_done;
      if (tx_done && tx_done < t) t= tx_done;
      if (rx_at && rx_at < t) t= rx_at;
      if (p1_high_at && p1_high_at < t) t= p1_high_at;
      if (p3_high_at && p3_high_at < t) t= p3_high_at;
      if (sweep_at && sweep_at < t) t= sweep_at;
      uint64_t d= t - now;
      /* PCA (datasheet, "PCA"): CMOD.CPS 000 SYSCLK/12 (the others: /2, timer 0, ECI,
       * SYSCLK, /4, /6, /8); CCON.CR runs it; CF on the 16-bit overflow; a PWM module
       * reloads CCAPnL from CCAPnH (and EPCnL from EPCnH) as CL overflows */
      if (c_ccon->get() & 0x40)
        {
          unsigned dv= pca_clocks();
          if (dv)
            {
              pca_sub+= (int)d;
              unsigned n= (unsigned)pca_sub / dv;
              pca_sub-= (int)(n * dv);
              if (n)
                {
                  uint32_t c= (c_ch->get() << 8) | c_cl->get();
                  uint32_t c2= c + n;
                  if ((c & 0xff) + n >= 256)
                    for (int m= 0; m < 2; m++)
                      if ((c_ccapm[m]->get() & 0x42) == 0x42)
                        {
                          c_ccapl[m]->set(c_ccaph[m]->get());
                          t_mem p= c_pwm[m]->get();
                          c_pwm[m]->set((p & ~1u) | ((p >> 1) & 1));
                        }
                  if (c2 > 0xffff)
                    c_ccon->set(c_ccon->get() | 0x80);
                  c_cl->set(c2 & 0xff);
                  c_ch->set((c2 >> 8) & 0xff);
                }
            }
        }
      /* watchdog: overflows after 12 * 2^(PS+1) * 32768 clocks */
      t_mem w= c_wdt->get();
      if ((w & 0x20) && !reset_due)
        {
          wdt_count+= d;
          if (wdt_count >= (uint64_t)12 * 32768u * (2u << (w & 7)))
            reset_due= true;
        }
      now= t;
      if (adc_done == now)
        {
          t_mem a= c_adc->get();
          uint16_t v= adc_in[a & 7] & 0x3ff;
          c_res->set(v >> 2);
          c_resl->set(v & 3);
          c_adc->set((a & ~0x08u) | 0x10);
          adc_done= 0;
        }
      if (tx_done == now)
        {
          c_scon->set(c_scon->get() | bmTI);
          tx_done= 0;
        }
      if (rx_at == now)
        {
          t_mem s= c_scon->get();
          rx_at= 0;
          /* mode 1/3 with REN: SBUF and RI when RI is clear (and, with SM2, a stop bit 1) */
          if ((s & 0x10) && !(s & bmRI) && rx_ok)
            {
              c_scon->set(s | bmRI);
              c_sbuf->set(rx_byte);
            }
        }
      if (p1_high_at == now)
        {
          p1_high_at= 0;
          port_pins(1, 0xff);
        }
      if (p3_high_at == now)
        {
          p3_high_at= 0;
          port_pins(3, 0xff);
        }
      if (sweep_at == now)
        {
          struct stc12_ev w= { now, STC12_EV_WHEEL, 1 };
          sweep_at= 0;
          apply(&w);
        }
      if (sweep && !sweep_at && (c_ccon->get() & 0x40) && ((c_cmod->get() >> 1) & 7) == 0)
        {
          /* the next edge: `off` clocks before the overflow after this one */
          uint32_t cnt= (c_ch->get() << 8) | c_cl->get();
          uint64_t ovf= now + (uint64_t)(0x10000 - cnt) * 12 - (uint64_t)pca_sub;
          uint64_t off= sweep_off + 3u * (sweep_k++ % 600u);
          if (ovf < now + off + 24)
            ovf+= (uint64_t)0x10000 * 12;
          sweep_at= ovf - off;
        }
    }
}
