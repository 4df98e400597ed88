/* stc12_link.cc: the STC12C5A60S2 model in lock step with the host's plant (stc12_link.h): the host's inputs at their clocks, the pins and frames reported, the main loop's passes, the interrupt handlers' time, the pass profile. */
/* This file is part of the sprayer project's patch to uCsim (GPL v2 or later, as uCsim). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "regs51.h"
#include "portcl.h"
#include "interruptcl.h"
#include "stc12cl.h"
#include "stc12_link.h"

void
cl_stc12hw::inst_begin(t_addr pc, uint64_t lag)
{
  uint64_t now= this->now + lag;      /* the clock at the instruction's start */
  t_mem sp= c_sp->get();
  if (sp > sp_max && pass_start)
    sp_max= (uint8_t)sp;        /* the stack's high-water mark once the main loop runs */
  if (pc == pass_pc && isr_depth == 0)
    {
      if (pass_start)
        {
          uint64_t d= now - pass_start;
          passes++;
          pass_sum+= (uint32_t)d;
          if (d > pass_max)
            {
              pass_max= (uint32_t)d;
              max_adc= pass_adc;
              max_iap= pass_iap;
            }
          if (pass_adc >= 8 && d > step_max)
            step_max= (uint32_t)d;
          if (prof_out)
            prof_pass_end((uint32_t)d);
        }
      pass_start= now;
      pass_adc= pass_iap= 0;
      prof_n= 0;
      prof_hit= false;
    }
  if ((long)pc == prof_at)
    prof_hit= true;
  if (prof_out && pass_start && prof_n < (1u << 22))
    {
      if (prof_n == prof_cap)
        {
          prof_cap= prof_cap ? 2 * prof_cap : 65536;
          prof_cur= (struct prof_rec *)realloc(prof_cur, prof_cap * sizeof *prof_cur);
        }
      prof_cur[prof_n].pc= (uint16_t)pc;
      prof_cur[prof_n].sp= (uint8_t)sp;
      prof_cur[prof_n].t= (uint32_t)(now - pass_start);
      prof_n++;
    }
}

/* a pass ended after d clocks: kept when it is the longest, the longest control step (8
 * conversions or more), the longest other pass begun from the first second on, or the longest
 * that ran the code at prof_at */
void
cl_stc12hw::prof_pass_end(uint32_t d)
{
  for (int k= 0; k < 4; k++)
    if (d > prof_keep_len[k]
        && (k == 0 || (k == 1 && pass_adc >= 8) || (k == 2 && pass_adc < 8 && pass_start >= STC12_SYSCLK_HZ)
            || (k == 3 && prof_hit)))
      {
        prof_keep[k]= (struct prof_rec *)realloc(prof_keep[k], (prof_n + 1) * sizeof *prof_cur);
        memcpy(prof_keep[k], prof_cur, prof_n * sizeof *prof_cur);
        prof_keep_n[k]= prof_n;
        prof_keep_len[k]= d;
        prof_keep_start[k]= pass_start;
        prof_keep_adc[k]= pass_adc;
      }
}

/* the kept passes, each instruction as PC, SP and its start clock in the pass (hex) */
void
cl_stc12hw::prof_write(void)
{
  static const char *name[4]= { "longest", "step", "other", "at" };
  for (int k= 0; k < 4; k++)
    {
      fprintf(prof_out, "pass %s start %llu clocks %u adc %u instructions %u\n", name[k],
              (unsigned long long)prof_keep_start[k], prof_keep_len[k], prof_keep_adc[k],
              prof_keep_n[k]);
      for (uint32_t i= 0; i < prof_keep_n[k]; i++)
        fprintf(prof_out, "%x %x %x\n", prof_keep[k][i].pc, prof_keep[k][i].sp, prof_keep[k][i].t);
    }
  fclose(prof_out);
  prof_out= NULL;
}

void
cl_stc12hw::isr_enter(t_addr vector, uint64_t lag)
{
  uint64_t now= this->now + lag;
  if (isr_depth < 8)
    {
      isr_stack[isr_depth].t= now;
      isr_stack[isr_depth].child= 0;
      isr_stack[isr_depth].v= (int)((vector - 3) / 8);
    }
  isr_depth++;
}

void
cl_stc12hw::isr_leave(uint64_t lag)
{
  uint64_t now= this->now + lag;
  if (isr_depth <= 0)
    return;
  isr_depth--;
  if (isr_depth < 8)
    {
      int v= isr_stack[isr_depth].v;
      uint64_t d= now - isr_stack[isr_depth].t, own= d - isr_stack[isr_depth].child;
      if (isr_depth > 0)
        isr_stack[isr_depth - 1].child+= d;
      if (v >= 0 && v < STC12_VECTORS)
        {
          vec[v].count++;
          vec[v].sum+= own;
          if (d > vec[v].max)
            vec[v].max= (uint32_t)d;
          if (own > vec[v].own_max)
            vec[v].own_max= (uint32_t)own;
        }
    }
}

uint64_t
cl_stc12hw::rd(int n)
{
  uint64_t v= 0;
  for (int i= 0; i < n; i++)
    {
      int c= fgetc(fin);
      if (c == EOF)
        exit(3);                /* the host went away */
      v|= (uint64_t)(c & 0xff) << (8 * i);
    }
  return v;
}

void
cl_stc12hw::wr(uint64_t v, int n)
{
  for (int i= 0; i < n; i++)
    fputc((int)((v >> (8 * i)) & 0xff), fout);
}

void
cl_stc12hw::link_config(void)
{
  if (fgetc(fin) != 'C')
    exit(3);
  for (unsigned i= 0; i < sizeof eeprom; i++)
    eeprom[i]= (uint8_t)rd(1);
  pass_pc= (t_addr)rd(2);
  n_watch= (uint8_t)rd(1);
  if (n_watch > 8)
    exit(3);
  for (int i= 0; i < n_watch; i++)
    {
      watch_addr[i]= (uint16_t)rd(2);
      watch_len[i]= (uint8_t)rd(1);
    }
}

void
cl_stc12hw::link_end(void)
{
  fputc('X', fout);
  wr(sp_max, 1);
  wr(STC12_VECTORS, 1);
  for (int v= 0; v < STC12_VECTORS; v++)
    {
      wr(3 + 8 * v, 2);
      wr(vec[v].count, 4);
      wr(vec[v].max, 4);
      wr(vec[v].own_max, 4);
      wr(vec[v].sum, 8);
    }
  fflush(fout);
  if (prof_out)
    prof_write();
  exit(0);
}

/* the slot's report, then the next slot's inputs */
void
cl_stc12hw::link_slot(void)
{
  if (slot_end)
    {
      uint8_t l1= (uint8_t)c_p1->get(), l3= (uint8_t)c_p3->get();
      uint8_t m0_1= (uint8_t)c_p1m0->get(), m1_1= (uint8_t)c_p1m1->get();
      uint8_t m0_3= (uint8_t)c_p3m0->get(), m1_3= (uint8_t)c_p3m1->get();
      uint16_t st= strong();
      unsigned pwm= pwm1();
      fputc('R', fout);
      wr(st & 0xff, 1);
      wr(st >> 8, 1);
      wr(l1 & ~m0_1 & ~m1_1, 1);
      wr(l3 & ~m0_3 & ~m1_3, 1);
      wr(pwm, 2);
      wr(resets, 1);
      wr(cause, 1);
      wr(passes, 2);
      wr(pass_max, 4);
      wr(pass_sum, 4);
      wr(max_adc, 1);
      wr(max_iap, 1);
      wr(step_max, 4);
      wr(early, 2);
      early= 0;
      wr(n_tx, 1);
      fwrite(tx_log, 12, n_tx, fout);
      for (int i= 0; i < n_watch; i++)
        for (int j= 0; j < watch_len[i]; j++)
          wr(xram->get(watch_addr[i] + j), 1);
      fflush(fout);
      resets= 0;
      passes= 0;
      pass_max= pass_sum= step_max= 0;
      max_adc= max_iap= 0;
      n_tx= 0;
    }
  int c= fgetc(fin);
  if (c == 'Q')
    link_end();
  if (c != 'S')
    exit(3);
  slot_end= rd(8);
  n_ev= (unsigned)rd(2);
  if (n_ev > cap_ev)
    {
      cap_ev= n_ev * 2;
      ev= (struct stc12_ev *)realloc(ev, cap_ev * sizeof *ev);
    }
  for (unsigned i= 0; i < n_ev; i++)
    {
      ev[i].clock= rd(8);
      ev[i].kind= (uint8_t)rd(1);
      ev[i].value= (uint32_t)rd(4);
    }
  i_ev= 0;
}

/* clocks from now until a peripheral changes by itself: the host's next input or the slot's
 * end, a completion (a conversion, a frame, a pulse's end, the sweep's edge), the PCA's
 * overflow (CF), the watchdog's; 0 from a reset to the first pass (the outputs watched at every
 * instruction) and without the link */
uint64_t
cl_stc12hw::quiet(void)
{
  if (!fin || !slot_end || !pass_start || reset_due || pin_reset)
    return 0;
  uint64_t due= slot_end;
  if (i_ev < n_ev && ev[i_ev].clock < due)
    due= ev[i_ev].clock;
  const uint64_t done[6]= { adc_done, tx_done, rx_at, p1_high_at, p3_high_at, sweep_at };
  for (int i= 0; i < 6; i++)
    if (done[i] && done[i] < due)
      due= done[i];
  if (c_ccon->get() & 0x40)
    {
      unsigned dv= pca_clocks();
      uint32_t c= (c_ch->get() << 8) | c_cl->get();
      if (dv && now + (uint64_t)(0x10000 - c) * dv - (uint64_t)pca_sub < due)
        due= now + (uint64_t)(0x10000 - c) * dv - (uint64_t)pca_sub;
    }
  t_mem w= c_wdt->get();
  if (w & 0x20)
    {
      uint64_t lim= (uint64_t)12 * 32768u * (2u << (w & 7));
      if (now + (wdt_count < lim ? lim - wdt_count : 0) < due)
        due= now + (wdt_count < lim ? lim - wdt_count : 0);
    }
  return due > now ? due - now : 0;
}

/* an input from the host at its clock */
void
cl_stc12hw::apply(const struct stc12_ev *e)
{
  switch (e->kind)
    {
    case STC12_EV_WHEEL:
      if (sweep && !e->value)
        break;                  /* the sweep's edges only */
      port_pins(3, 0xff & ~0x04);
      p3_high_at= now + STC12_PULSE_CLOCKS;
      break;
    case STC12_EV_METER:
      port_pins(1, 0xff & ~0x08);
      p1_high_at= now + STC12_PULSE_CLOCKS;
      /* CCAPM0.CAPN: a falling edge on CCP0 latches CL/CH into CCAP0L/H and sets CCF0 */
      if ((c_ccapm[0]->get() & 0x10) && (c_ccon->get() & 0x40))
        {
          c_ccapl[0]->set(c_cl->get());
          c_ccaph[0]->set(c_ch->get());
          c_ccon->set(c_ccon->get() | 0x01);
        }
      break;
    case STC12_EV_RX:
      {
        /* the receiver samples the sender's frame at the middle of each of its own bits */
        unsigned sb= (e->value >> 8) & 0xffff, stop= e->value >> 24, rb= bit_clocks();
        uint8_t b= (uint8_t)e->value, got= 0;
        int data= 8;
        if (!rb || !sb)
          break;
        for (int i= 0; i <= data; i++)
          {
            unsigned k= (unsigned)(((i + 1) * 2 + 1) * (uint64_t)rb / 2 / sb);  /* sender's bit index */
            int level= k == 0 ? 0 : k <= 8 ? (b >> (k - 1)) & 1 : 1;
            if (i < data)
              got|= (uint8_t)(level << i);
            else
              rx_ok= (uint8_t)level;    /* the stop bit (RB8) */
          }
        (void)stop;
        rx_byte= got;
        rx_at= now + (uint64_t)rb * 19 / 2;
        break;
      }
    case STC12_EV_ADC:
      adc_in[(e->value >> 12) & 7]= (uint16_t)(e->value & 0x3ff);
      break;
    case STC12_EV_KEYS:
      keys= (uint16_t)e->value;
      keypad();
      break;
    case STC12_EV_P0:
      port_pins(0, e->value & 0xff);
      break;
    case STC12_EV_RESET:
      pin_reset= true;
      break;
    case STC12_EV_HANG:
      hung= true;
      break;
    case STC12_EV_WHEEL_SWEEP:
      sweep= true;
      sweep_off= e->value;
      sweep_k= 0;
      break;
    }
}

/* the output pins driving high now: push-pull (PxM1 = 0, PxM0 = 1) with the latch at 1, P1.4
 * the PCA's PWM where module 1 is in PWM mode; P1 low byte, P3 high byte */
uint16_t
cl_stc12hw::strong(void)
{
  uint8_t l1= (uint8_t)c_p1->get(), l3= (uint8_t)c_p3->get();
  if ((c_ccapm[1]->get() & 0x42) == 0x42)
    l1= (uint8_t)((l1 & ~0x10) | (pwm1() ? 0x10 : 0));
  return (uint16_t)((l1 & c_p1m0->get() & ~c_p1m1->get() & 0xff)
                    | (((l3 & c_p3m0->get() & ~c_p3m1->get()) & 0xff) << 8));
}

/* module 1's high time in 256ths of the PWM period: {EPC1L, CCAP1L} against {0, CL} */
unsigned
cl_stc12hw::pwm1(void)
{
  if ((c_ccapm[1]->get() & 0x42) != 0x42)
    return 0;
  return (c_pwm[1]->get() & 1) ? 0 : 256 - c_ccapl[1]->get();
}

int
cl_stc12hw::tick(int cycles)
{
  uint64_t to= now + (uint64_t)cycles;
  if (!pass_start)
    early|= strong();
  if (fin && !slot_end)
    {
      link_config();
      link_slot();
    }
  if ((uint8_t)c_p2->get() != p2_latch)
    {
      p2_latch= (uint8_t)c_p2->get();   /* a keypad row driven: the columns follow */
      keypad();
    }
  for (;;)
    {
      uint64_t lim= to;
      if (fin && slot_end < lim)
        lim= slot_end;
      while (i_ev < n_ev && ev[i_ev].clock <= lim)
        {
          advance(ev[i_ev].clock);
          apply(&ev[i_ev]);
          i_ev++;
        }
      advance(lim);
      if (fin && now >= slot_end)
        {
          link_slot();
          continue;
        }
      if (now >= to)
        break;
    }
  return 0;
}
