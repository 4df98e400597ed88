/* stc12.cc: the STC12C5A60S2 in uCsim's s51 (-t STC12): 1T instruction timing, its SFRs as the datasheet gives them, the lock-step link to the host's plant. */
/* This file is part of the sprayer project's patch to uCsim (GPL v2 or later, as uCsim). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "regs51.h"
#include "portcl.h"
#include "interruptcl.h"
#include "stc12cl.h"
#include "stc12_link.h"

/* ---- the 1T core ------------------------------------------------------------------------ */
/* Clocks of each opcode (STC12C5Axx datasheet, "Instruction set summary", the column of the
 * STC12 1T core; a conditional jump takes the same clocks taken or not). */
static const uint8_t clk1t[256]= {
/*        0  1  2  3  4  5  6  7  8  9  a  b  c  d  e  f */
/* 0 */   1, 3, 4, 1, 2, 4, 4, 4, 3, 3, 3, 3, 3, 3, 3, 3,
/* 1 */   5, 6, 6, 1, 2, 4, 4, 4, 3, 3, 3, 3, 3, 3, 3, 3,
/* 2 */   4, 3, 4, 1, 2, 2, 2, 2, 1, 1, 1, 1, 1, 1, 1, 1,
/* 3 */   4, 6, 4, 1, 2, 2, 2, 2, 1, 1, 1, 1, 1, 1, 1, 1,
/* 4 */   3, 3, 3, 4, 2, 2, 2, 2, 1, 1, 1, 1, 1, 1, 1, 1,
/* 5 */   3, 6, 3, 4, 2, 2, 2, 2, 1, 1, 1, 1, 1, 1, 1, 1,
/* 6 */   3, 3, 3, 4, 2, 2, 2, 2, 1, 1, 1, 1, 1, 1, 1, 1,
/* 7 */   3, 6, 3, 3, 2, 3, 3, 3, 2, 2, 2, 2, 2, 2, 2, 2,
/* 8 */   3, 3, 3, 4, 5, 4, 4, 4, 3, 3, 3, 3, 3, 3, 3, 3,
/* 9 */   3, 6, 4, 4, 2, 2, 2, 2, 1, 1, 1, 1, 1, 1, 1, 1,
/* a */   3, 3, 3, 1, 4, 1, 5, 5, 4, 4, 4, 4, 4, 4, 4, 4,
/* b */   3, 6, 4, 1, 4, 5, 5, 5, 4, 4, 4, 4, 4, 4, 4, 4,
/* c */   4, 3, 4, 1, 1, 4, 4, 4, 3, 3, 3, 3, 3, 3, 3, 3,
/* d */   3, 6, 4, 1, 4, 5, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4,
/* e */   3, 3, 3, 3, 1, 2, 2, 2, 1, 1, 1, 1, 1, 1, 1, 1,
/* f */   3, 6, 4, 4, 2, 3, 3, 3, 2, 2, 2, 2, 2, 2, 2, 2,
};
#define STC12_IRQ_CLOCKS 6      /* the hardware's LCALL to the vector */

/* The operand of each opcode that names a direct byte (1: the byte after the opcode; 3: both,
 * MOV dir,dir) or a bit (2) (datasheet, "Instruction set summary"). */
static uint8_t operand[256];

static void
operand_init(void)
{
  static const uint8_t dir[]= { 0x05, 0x15, 0x25, 0x35, 0x42, 0x43, 0x45, 0x52, 0x53, 0x55, 0x62, 0x63,
                                0x65, 0x75, 0x86, 0x87, 0x95, 0xa6, 0xa7, 0xb5, 0xc0, 0xc5, 0xd0, 0xd5,
                                0xe5, 0xf5 };
  static const uint8_t bit[]= { 0x10, 0x20, 0x30, 0x72, 0x82, 0x92, 0xa0, 0xa2, 0xb0, 0xb2, 0xc2, 0xd2 };
  for (unsigned i= 0; i < sizeof dir; i++)
    operand[dir[i]]= 1;
  for (int i= 0; i < 8; i++)
    operand[0x88 + i]= operand[0xa8 + i]= 1;
  operand[0x85]= 3;
  for (unsigned i= 0; i < sizeof bit; i++)
    operand[bit[i]]= 2;
}

cl_stc12::cl_stc12(struct cpu_entry *Itype, class cl_sim *asim):
  cl_uc52(Itype, asim), hw(NULL), in_inst(false), lag(0), room(0), stale(false), it_dirty(true)
{
}

void
cl_stc12::mk_hw_elements(void)
{
  class cl_hw *h;
  operand_init();
  cl_uc::mk_hw_elements();
  acc= sfr->get_cell(ACC);
  psw= sfr->get_cell(PSW);
  add_hw(h= t0= new cl_stc12_timer(this, 0, "timer0"));
  h->init();
  add_hw(h= t1= new cl_stc12_timer(this, 1, "timer1"));
  h->init();
  for (int i= 0; i < 4; i++)
    {
      class cl_port *p;
      add_hw(p= new cl_port(this, i));
      p->init();
    }
  add_hw(interrupt= new cl_interrupt(this));
  interrupt->init();
  add_hw(hw= new cl_stc12hw(this));
  hw->init();
  c_ie= sfr->get_cell(IE);
  c_tcon= sfr->get_cell(TCON);
  c_scon= sfr->get_cell(SCON);
  c_adc= sfr->get_cell(0xbc);
  c_pcon= sfr->get_cell(PCON);
  c_ccon= sfr->get_cell(0xd8);
  c_cmod= sfr->get_cell(0xd9);
  c_ccapm0= sfr->get_cell(0xda);
  c_ccapm1= sfr->get_cell(0xdb);
}

/* an SFR of a peripheral: any but the core's own SP, DPL, DPH, PSW, ACC and B */
static bool
periph_sfr(t_mem a)
{
  return a >= 0x80 && a != 0x81 && a != 0x82 && a != 0x83 && a != 0xd0 && a != 0xe0 && a != 0xf0;
}

/* the instruction at instPC reads or writes a peripheral's SFR (or one of its bits) */
bool
cl_stc12::touches_hw(uint8_t op)
{
  switch (operand[op])
    {
    case 0: return false;
    case 1: return periph_sfr(rom->get(instPC + 1));
    case 2: { t_mem b= rom->get(instPC + 1); return b >= 0x80 && periph_sfr(b & 0xf8); }
    default: return periph_sfr(rom->get(instPC + 1)) || periph_sfr(rom->get(instPC + 2));
    }
}

/* The peripherals are given the core's clocks only when what they do could show: before an
 * instruction that reads or writes one of their SFRs (and after it, the time to their next
 * change taken again), at an interrupt's entry and RETI, and when the clocks reach the next
 * change they make by themselves (quiet()). Each then gets the clocks as one span, as every
 * one of them counts spans; between two such points nothing the core reads or the host is sent
 * depends on them, so a run is the same as with a tick every instruction. */
void
cl_stc12::clocks(int n)
{
  lag+= (uint64_t)n;
  if (lag >= room)
    catch_up();
}

void
cl_stc12::catch_up(void)
{
  int n= (int)lag;
  lag= 0;
  if (n)
    cl_uc::tick(n);
  room= quiet();
  it_dirty= true;
}

/* clocks until a peripheral changes by itself: the timers' overflows, the host's next input,
 * the chip's completions. A low level on INT0/INT1 in level mode raises its flag again at every
 * look: with it cleared (an SFR write), the next instruction looks, as a tick every instruction
 * would (an interrupt's acceptance looks itself). */
uint64_t
cl_stc12::quiet(void)
{
  t_mem tcon= c_tcon->get();
  if ((!interrupt->bit_IT0 && !interrupt->bit_INT0 && !(tcon & bmIE0))
      || (!interrupt->bit_IT1 && !interrupt->bit_INT1 && !(tcon & bmIE1)))
    return 0;
  uint64_t r= hw->quiet(), q;
  if ((q= ((class cl_stc12_timer *)t0)->room()) < r)
    r= q;
  if ((q= ((class cl_stc12_timer *)t1)->room()) < r)
    r= q;
  return r;
}

int
cl_stc12::tickt(t_mem code)
{
  uint8_t op= (uint8_t)code;
  hw->inst_begin(instPC, lag);
  in_inst= true;
  if (op == 0x32 || touches_hw(op))
    {
      lag+= clk1t[op];          /* RETI, or a peripheral's SFR: up to date before it runs */
      catch_up();
      stale= true;              /* what it writes may change quiet() */
      if (op == 0x32)
        hw->isr_leave(lag);
      return 0;
    }
  if (stale)
    {
      room= quiet();
      stale= false;
    }
  clocks(clk1t[op]);
  return 0;
}

/* the instruction handlers' own machine-cycle ticks: charged already by tickt */
int
cl_stc12::tick(int cycles)
{
  if (!in_inst)
    clocks(cycles);
  return 0;
}

/* the peripherals that count time, each ticked once with the clocks that passed (each one
 * handles a span; uCsim's own loop ticks every peripheral a clock at a time) */
int
cl_stc12::tick_hw(int cycles)
{
  t0->tick(cycles);
  t1->tick(cycles);
  interrupt->tick(cycles);
  hw->tick(cycles);
  do_extra_hw(cycles);
  return 0;
}

/* in lock step the host holds the console: no breakpoint to look for at each fetch */
bool
cl_stc12::fetch(t_mem *code)
{
  if (!hw->linked())
    return cl_uc::fetch(code);
  *code= cl_uc::fetch();
  return false;
}

/* PCON's IDL and PD, the rare case, in uCsim's own code */
int
cl_stc12::idle_pd(void)
{
  return (c_pcon->get() & (bmIDL | bmPD)) ? cl_51core::idle_pd() : resGO;
}

int
cl_stc12::exec_inst(void)
{
  int r;
  if (hw->reset_due || hw->pin_reset)
    {
      catch_up();
      reset();
      return resGO;
    }
  in_inst= false;
  if (hw->hung)
    {
      clocks(3);                /* an SJMP to itself, interrupts still served */
      return resGO;
    }
  if (hw->stall)
    {
      int s= hw->stall;         /* IAP holds the CPU; the peripherals run on */
      hw->stall= 0;
      clocks(s);
      return resGO;
    }
  in_inst= false;
  r= cl_51core::exec_inst();
  in_inst= false;
  return r;
}

/* In lock step with the host, a step of uCsim's main loop runs up to a thousand instructions
 * (the batch ends early at an interrupt): the loop's own work (its console, its history) costs
 * about what an instruction does. */
int
cl_stc12::do_inst(int step)
{
  return cl_51core::do_inst(step == 1 && hw && hw->linked() ? 1000 : step);
}

/* four levels from IP and IPH (datasheet, "Interrupt priority"); IP and IPH hold a source's
 * bits where IE holds its enable (the PCA's at bit 7) */
int
cl_stc12::priority_of(uchar nuof_it)
{
  return ((sfr->get(IPH) & nuof_it) ? 2 : 0) + ((sfr->get(IP) & nuof_it) ? 1 : 0);
}

/* the highest level pending above the one being served; on a tie, the lower vector (the
 * datasheet's polling order) */
int
cl_stc12::do_interrupt(void)
{
  if (interrupt->was_reti)
    {
      interrupt->was_reti= false;
      return resGO;
    }
  if (!it_dirty)
    return resGO;               /* no flag, enable or level changed since the last look */
  it_dirty= false;
  if (!(c_ie->get() & bmEA))
    return resGO;
  /* no enabled source with its flag up: nothing to look for */
  t_mem ie= c_ie->get(), tcon= c_tcon->get(), ccon= c_ccon->get();
  if (!((ie & 0x01) && (tcon & 0x02)) && !((ie & 0x02) && (tcon & 0x20))
      && !((ie & 0x04) && (tcon & 0x08)) && !((ie & 0x08) && (tcon & 0x80))
      && !((ie & 0x10) && (c_scon->get() & 3)) && !((ie & 0x20) && (c_adc->get() & 0x10))
      && !((ie & 0x40) && (c_pcon->get() & 0x20))
      && !((ccon & 0x80) && (c_cmod->get() & 1)) && !((ccon & 0x01) && (c_ccapm0->get() & 1))
      && !((ccon & 0x02) && (c_ccapm1->get() & 1)))
    return resGO;
  class it_level *il= (class it_level *)(it_levels->top());
  class cl_it_src *best= NULL;
  int bp= -1;
  for (int i= 0; i < it_sources->count; i++)
    {
      class cl_it_src *is= (class cl_it_src *)(it_sources->at(i));
      if (!is->is_active() || !is->enabled() || !is->pending())
        continue;
      int pr= priority_of(is->ie_mask);
      if (il->level >= 0 && pr <= il->level)
        continue;
      if (pr > bp || (pr == bp && is->addr < best->addr))
        {
          best= is;
          bp= pr;
        }
    }
  if (!best)
    return resGO;
  best->clear();
  return accept_it(new it_level(bp, best->addr, PC, best));
}

int
cl_stc12::accept_it(class it_level *il)
{
  state= stGO;
  catch_up();                   /* the clocks before at the old level (uCsim's ISR counter) */
  it_levels->push(il);
  hw->isr_enter(il->addr, lag);
  in_inst= false;
  clocks(STC12_IRQ_CLOCKS);
  in_inst= true;
  int res= inst_lcall(0, il->addr, true);
  in_inst= false;
  it_dirty= true;
  return res != resGO ? res : resINTERRUPT;
}

void
cl_stc12::reset(void)
{
  t_mem pcon= sfr ? sfr->get(PCON) : 0;
  cl_51core::reset();
  if (hw)
    hw->chip_reset(pcon);
}

int
cl_stc12_timer::tick(int cycles)
{
  int n= cycles;
  if (!auxr)
    auxr= uc->address_space(MEM_SFR_ID)->get_cell(0x8e);
  if (!(auxr->get() & (id == 0 ? 0x80 : 0x40)))   /* T0x12 / T1x12: SYSCLK, else SYSCLK/12 */
    {
      sub+= cycles;
      if (sub < 12)
        return resGO;
      n= sub / 12;
      sub-= 12 * n;
    }
  if (mode != 1 || C_T || GATE)
    return cl_timer0::tick(n);
  if (!TR)
    return resGO;
  /* mode 1, a span at once: TH:TL counts, TF on the overflow */
  unsigned v= (cell_th->get() << 8 | cell_tl->get()) + (unsigned)n;
  cell_tl->set(v & 0xff);
  cell_th->set((v >> 8) & 0xff);
  if (v > 0xffff)
    {
      cell_tcon->set(cell_tcon->get() | mask_TF);
      overflow();
    }
  return resGO;
}

/* clocks until the timer overflows (TF): it may lag that long; 0 in a mode tick() does not
 * count in spans (0, 2, 3, a counter, a gate) */
uint64_t
cl_stc12_timer::room(void)
{
  if (!auxr || mode == 3)
    return 0;
  if (!TR)
    return UINT64_MAX;
  if (mode != 1 || C_T || GATE)
    return 0;
  uint64_t left= 0x10000 - (cell_th->get() << 8 | cell_tl->get());
  return (auxr->get() & (id == 0 ? 0x80 : 0x40)) ? left : left * 12 - (uint64_t)sub;
}

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

/* SYSCLK clocks a PCA count by CMOD.CPS (datasheet, "PCA"): /12, /2, timer 0's overflow and
 * ECI not modelled (0), SYSCLK, /4, /6, /8 */
static const unsigned pca_div[8]= { 12, 2, 0, 0, 1, 4, 6, 8 };

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
      unsigned dv= pca_div[(c_cmod->get() >> 1) & 7];
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
          unsigned dv= pca_div[(c_cmod->get() >> 1) & 7];
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
