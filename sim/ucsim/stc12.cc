/* stc12.cc: the STC12C5A60S2 in uCsim's s51 (-t STC12): the 1T core's timing, its interrupts, the peripherals' clocks, timers 0 and 1 (stc12_hw.cc: the peripherals; stc12_link.cc: the host's link). */
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
  every= getenv("STC12_EVERY_INSTRUCTION") != NULL;
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
  if (every)
    return 0;
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
      room= 0;                  /* to the first pass every instruction: the outputs watched */
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
  r= cl_51core::exec_inst();
  in_inst= false;
  return r;
}

/* In lock step with the host, a step of uCsim's main loop runs up to a thousand instructions
 * (the batch ends at an interrupt's acceptance), each without what only the console uses (the
 * disassembler's marks of code cells, a stop on a jump to itself): uCsim's loop around an
 * instruction costs about what the instruction does. Otherwise uCsim's own loop. */
int
cl_stc12::do_inst(int step)
{
  if (step != 1 || !hw->linked())
    return cl_51core::do_inst(step);
  result= resGO;
  for (int n= 0; n < 1000 && result == resGO && state != stPD; n++)
    {
      if (state == stGO)
        {
          interrupt->was_reti= false;
          pre_inst();
          result= exec_inst();
          post_inst();
        }
      else
        tick(1);
      if (result == resGO)
        {
          int res= do_interrupt();
          result= res != resGO ? res : idle_pd();
        }
    }
  if (result >= resSTOP || (result == resINTERRUPT && stop_at_it))
    sim->stop(result);
  return result;
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
